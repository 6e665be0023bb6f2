"""ros/launch/tum.launch with ros/ as the ROS package `lrdslam` (README, "On a robot with ROS"):
roslaunch parses it, starts the node, rosbag play and rviz, and finds the node through
ros/scripts/lrdslam_ros, which runs the CMake-built binary."""
import os
import subprocess
from pathlib import Path

ROS_DIR = Path(__file__).resolve().parents[3] / "ros"


def roslaunch(*args):
    env = dict(os.environ, ROS_PACKAGE_PATH=str(ROS_DIR))
    return subprocess.run(["roslaunch", *args, str(ROS_DIR / "launch" / "tum.launch"), "bag:=/data/x.bag"],
                          capture_output=True, text=True, env=env, timeout=60)


def test_the_launch_file_starts_the_node_the_player_and_rviz():
    r = roslaunch("--nodes")
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["/lrdslam", "/player", "/rviz"]


def test_roslaunch_runs_the_built_node_with_its_parameters():
    r = roslaunch("--args", "/lrdslam")
    assert r.returncode == 0, r.stderr
    assert str(ROS_DIR / "scripts" / "lrdslam_ros") in r.stdout and "__name:=lrdslam" in r.stdout
    r = roslaunch("--args", "/player")
    assert "play -q -d 2 -r 1.0 /data/x.bag" in r.stdout
    dump = roslaunch("--dump-params")
    assert dump.returncode == 0, dump.stderr
    assert "/lrdslam/mode: full" in dump.stdout and "/lrdslam/queue_size: 2" in dump.stdout


def test_the_wrapper_runs_the_binary_it_is_given(tmp_path):
    fake = tmp_path / "node"
    fake.write_text("#!/bin/sh\necho ran \"$@\"\n")
    fake.chmod(0o755)
    r = subprocess.run([str(ROS_DIR / "scripts" / "lrdslam_ros"), "__name:=x"], capture_output=True, text=True,
                       env=dict(os.environ, LRDSLAM_ROS_BIN=str(fake)))
    assert r.stdout.strip() == "ran __name:=x"
    r = subprocess.run([str(ROS_DIR / "scripts" / "lrdslam_ros")], capture_output=True, text=True,
                       env=dict(os.environ, LRDSLAM_ROS_BIN=str(tmp_path / "missing")))
    assert r.returncode == 1 and "not found: build it first" in r.stderr
