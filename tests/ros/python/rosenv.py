"""The real ROS 1 tools for the node tests: a roscore of our own on a free port of 127.0.0.1
(ROS_MASTER_URI set for these tests only), the node, rosbag play, and rospy in this process."""
import os
import signal
import socket
import subprocess
import time

NODE_BIN = os.environ.get("LRDSLAM_ROS_BIN", "build/release/bin/lrdslam_ros")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class RosMaster:
    """roscore on a free port; its environment is this process's from start() on (rospy reads it)."""

    def __init__(self, home):
        self.port = free_port()
        self.env = dict(os.environ)
        self.env.update(
            ROS_MASTER_URI=f"http://127.0.0.1:{self.port}",
            ROS_HOSTNAME="127.0.0.1",
            ROS_HOME=str(home),
            ROS_LOG_DIR=str(home / "log"),
        )
        self.process = None

    def start(self):
        os.environ.update({k: self.env[k] for k in ("ROS_MASTER_URI", "ROS_HOSTNAME", "ROS_HOME", "ROS_LOG_DIR")})
        self.process = subprocess.Popen(["roscore", "-p", str(self.port)], env=self.env,
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                        start_new_session=True)
        import rosgraph

        deadline = time.time() + 60
        while time.time() < deadline:
            if rosgraph.Master("/lrdslam_test", master_uri=self.env["ROS_MASTER_URI"]).is_online():
                return self
            if self.process.poll() is not None:
                raise AssertionError(f"roscore exited with {self.process.returncode}")
            time.sleep(0.2)
        raise AssertionError("roscore did not come up within 60 s")

    def stop(self):
        if self.process and self.process.poll() is None:
            os.killpg(self.process.pid, signal.SIGINT)
            try:
                self.process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(self.process.pid, signal.SIGKILL)
                self.process.wait()


class Node:
    """lrdslam_ros (binary, default $LRDSLAM_ROS_BIN) as `lrdslam` with private parameters."""

    def __init__(self, master, log, binary=None, **params):
        # Private parameters outlive their node on the master: a previous node's must not leak in.
        import rospy

        if rospy.has_param("/lrdslam"):
            rospy.delete_param("/lrdslam")
        args = [binary or NODE_BIN, "__name:=lrdslam"] + [f"_{k}:={v}" for k, v in params.items()]
        self.log = log
        self.process = subprocess.Popen(args, env=master.env, stdout=open(log, "w"), stderr=subprocess.STDOUT)

    def wait_ready(self, timeout=60):
        import rosservice

        deadline = time.time() + timeout
        while time.time() < deadline:
            if self.process.poll() is not None:
                raise AssertionError(f"the node exited with {self.process.returncode}:\n{self.output()}")
            try:
                if "/lrdslam/save_trajectory" in rosservice.get_service_list():
                    return self
            except Exception:  # the master is busy: try again
                pass
            time.sleep(0.2)
        raise AssertionError(f"the node did not advertise its services within {timeout} s:\n{self.output()}")

    def interrupt(self, timeout=300):
        """SIGINT, then the exit status (the node finishes its queue and writes its files). The dense
        stage works at the lowest priority: on a loaded machine under ASan its backlog of keyframes
        takes minutes."""
        self.process.send_signal(signal.SIGINT)
        try:
            return self.process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.process.kill()
            raise AssertionError(f"the node did not exit within {timeout} s of SIGINT:\n{self.output()}")

    def kill(self):
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()

    def output(self):
        with open(self.log) as f:
            return f.read()


# What the node subscribes to by default (TUM's topics); the bag's /tf has no subscriber.
NODE_TOPICS = ("/camera/rgb/image_color", "/camera/depth/image", "/camera/rgb/camera_info")


def play(master, bag, rate, delay=1.0, topics=NODE_TOPICS):
    """rosbag play of these topics of the bag (blocks until it is played). It starts once each topic
    has a connected subscriber: a fixed delay alone lost the first seconds of the bag when a loaded
    machine was slow to connect the node."""
    subprocess.run(["rosbag", "play", "-q", "-d", str(delay), "-r", str(rate), "--wait-for-subscribers", str(bag),
                    "--topics", *topics], env=master.env, check=True, stdout=subprocess.DEVNULL, timeout=900)
