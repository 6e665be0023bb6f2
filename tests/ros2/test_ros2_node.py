"""lrdslam_ros2 against a ROS 2 participant that is not ours: Foxglove's @foxglove/ros2 (a pure
JavaScript RTPS/ROS 2 implementation, tests/ros2/ros2_listener.cjs) subscribes to the node's
topics over UDP on 127.0.0.1 while `lrdslam ros2-play` publishes a walking sequence as a camera
driver would; every message is decoded by @foxglove/rosmsg2-serialization against the official
ROS 2 definitions. Checks the poses' ATE against the ground truth, every field of the decoded
messages, transient-local delivery to a late subscriber, the node in the ROS graph
(ros_discovery_info), malformed input dropped and counted, and the command line. Each test has a
ROS_DOMAIN_ID of its own. Skips without Node.js and the packages of scripts/fetch-ros2-test-peers.sh."""
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))
from cli import BIN as CLI_BIN, lrdslam, synth_input  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
MODULES = ROOT / "data" / "npm-ros2" / "node_modules"
LISTENER = ROOT / "tests" / "ros2" / "ros2_listener.cjs"
NODE_BIN = os.environ.get("LRDSLAM_ROS2_BIN", "build/release/bin/lrdslam_ros2")
PUBLISHER_BIN = os.environ.get("LRDSLAM_ROS2_PUBLISHER_BIN", "build/release/bin/lrdslam_ros2_test_publisher")
FRAMES = 90
RATE = float(os.environ.get("LRDSLAM_ROS2_TEST_RATE", "0.5"))

pytestmark = pytest.mark.skipif(
    shutil.which("node") is None or not (MODULES / "@foxglove" / "ros2").is_dir(),
    reason="needs node and the npm packages scripts/fetch-ros2-test-peers.sh fetches into data/npm-ros2")

OUTPUTS = {"/lrdslam/pose": "geometry_msgs/msg/PoseStamped", "/lrdslam/path": "nav_msgs/msg/Path",
           "/lrdslam/state": "std_msgs/msg/String", "/lrdslam/occupancy": "nav_msgs/msg/OccupancyGrid",
           "/lrdslam/map_points": "sensor_msgs/msg/PointCloud2",
           "/lrdslam/keyframes": "visualization_msgs/msg/MarkerArray"}


def env(domain):
    return {**os.environ, "ROS_DOMAIN_ID": str(domain), "ROS_LOCALHOST_ONLY": "1"}


def wait_for_line(path, text, timeout, process):
    end = time.time() + timeout
    while time.time() < end:
        if path.exists() and text in path.read_text():
            return
        assert process.poll() is None, f"exited {process.returncode}:\n{path.read_text()}"
        time.sleep(0.05)
    raise AssertionError(f"no '{text}' within {timeout} s:\n{path.read_text()}")


class Node:
    """lrdslam_ros2 with --ros-args, its log in a file."""

    def __init__(self, domain, log, *ros_args):
        self.log = log
        with open(log, "w") as f:
            self.p = subprocess.Popen([NODE_BIN, "--ros-args", "-r", "__node:=lrdslam", *map(str, ros_args)],
                                      stdout=f, stderr=subprocess.STDOUT, env=env(domain))

    def wait_ready(self):
        wait_for_line(self.log, "node /lrdslam in domain", 30, self.p)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.p.poll() is None:
            self.p.kill()

    def interrupt(self, timeout=120):
        self.p.send_signal(signal.SIGINT)
        return self.p.wait(timeout)

    def output(self):
        return self.log.read_text()


class Listener:
    """ros2_listener.cjs on the node's topics, JSON lines into a file."""

    def __init__(self, domain, out, *args):
        self.out, self.err = out, out.with_suffix(".err")
        topics = [a for t, ty in OUTPUTS.items() for a in ("--topic", f"{t}:{ty}")]
        with open(self.err, "w") as f:
            self.p = subprocess.Popen(["node", LISTENER, "--domain", str(domain), "--seconds", "300", "--out", out,
                                       *topics, *map(str, args)], stderr=f, env=env(domain))
        wait_for_line(self.err, "listening on domain", 30, self.p)

    def stop(self, timeout=30):
        if self.p.poll() is None:
            self.p.send_signal(signal.SIGINT)
        self.p.wait(timeout)
        lines = [json.loads(l) for l in self.out.read_text().splitlines() if l.strip()]
        assert lines and lines[-1].get("done"), self.err.read_text()
        return lines


def messages(lines, topic):
    return sorted((l for l in lines if l.get("topic") == topic), key=lambda l: l["seq"])


def stamp(header):
    return header["stamp"]["sec"] + header["stamp"]["nanosec"] * 1e-9


@pytest.fixture(scope="module")
def sequence(tmp_path_factory):
    d = tmp_path_factory.mktemp("ros2") / "seq"
    synth_input("--preset", "walking_xyz", "--frames", FRAMES, "--out", d)
    return d


@pytest.fixture(scope="module")
def run(sequence, tmp_path_factory):
    """The node in `full` mode with the dense stage, a listener from the start, the sequence
    played, a late listener after the node has tracked it, then SIGINT."""
    tmp = tmp_path_factory.mktemp("ros2run")
    domain = 61
    out = tmp / "out"
    with Node(domain, tmp / "node.log", "-p", "mode:=full", "-p", "dense:=true", "-p", f"output_dir:={out}",
              "-p", "queue_size:=200") as node:
        node.wait_ready()
        first = Listener(domain, tmp / "first.jsonl", "--discovery")
        play = subprocess.run([CLI_BIN, "ros2-play", "--sequence", sequence, "--rate", str(RATE), "--wait", "30"],
                              capture_output=True, text=True, env=env(domain), timeout=300)
        assert play.returncode == 0 and f"{FRAMES} frames published" in play.stdout, play.stdout + play.stderr
        # The late subscriber: everything transient-local, with the node still up.
        late = Listener(domain, tmp / "late.jsonl", "--until-count", "/lrdslam/pose=10", "--until-count",
                        "/lrdslam/path=1", "--until-count", "/lrdslam/state=1", "--until-count",
                        "/lrdslam/map_points=1", "--until-count", "/lrdslam/occupancy=1")
        late.p.wait(60)
        late_lines = late.stop()
        status = node.interrupt()
        time.sleep(1)  # the path republished at the save
        first_lines = first.stop()
    assert status == 0, node.output()
    summary = json.loads((out / "node_summary.json").read_text())
    return {"first": first_lines, "late": late_lines, "summary": summary, "out": out, "node": node.output(),
            "tmp": tmp}


def test_the_autosave_parameter_keeps_a_loadable_map_while_the_node_runs(sequence, tmp_path):
    # A node of its own (static mode, a light load), so that the main run keeps its timing.
    domain = 65
    out = tmp_path / "out"
    with Node(domain, tmp_path / "node.log", "-p", "mode:=static", "-p", f"output_dir:={out}", "-p",
              "queue_size:=200", "-p", "autosave:=0.5") as node:
        node.wait_ready()
        play = subprocess.run([CLI_BIN, "ros2-play", "--sequence", sequence, "--rate", str(RATE), "--frames", "40",
                               "--wait", "30"], capture_output=True, text=True, env=env(domain), timeout=300)
        assert play.returncode == 0, play.stdout + play.stderr
        # What the autosave wrote while the node ran (the stop writes its final map over it): a save
        # with at least 10 poses (under a sanitizer tracking may lag the player by seconds).
        trajectory = out / "CameraTrajectory.txt"
        end = time.time() + 60
        while time.time() < end and not ((out / "map.lrdmap").exists() and trajectory.exists() and
                                         len(np.loadtxt(trajectory, ndmin=2)) >= 10):
            time.sleep(0.2)
        autosaved = tmp_path / "autosaved.lrdmap"
        shutil.copyfile(out / "map.lrdmap", autosaved)
        autosaved_poses = len(np.loadtxt(trajectory, ndmin=2))
        status = node.interrupt()
    assert status == 0, node.output()
    info = subprocess.run([CLI_BIN, "map", "info", autosaved, out / "map.lrdmap"], capture_output=True, text=True,
                          timeout=60)
    assert info.returncode == 0, info.stderr
    autosaved_keyframes, final_keyframes = [int(line.split(": ")[1].split()[0]) for line in info.stdout.splitlines()]
    assert 1 <= autosaved_keyframes <= final_keyframes, info.stdout
    tracked = json.loads((out / "node_summary.json").read_text())["tracked"]
    assert 10 <= autosaved_poses <= tracked, (tracked, autosaved_poses)


def test_poses_reach_an_independent_ros2_subscriber_within_2cm_of_the_ground_truth(run, sequence):
    s = run["summary"]
    assert s["malformed"] == 0 and s["no_camera"] == 0 and s["lost"] == 0, (s, run["node"])
    # Best-effort images over UDP may lose a frame at start; most must arrive and all be tracked.
    assert s["received"] >= 0.8 * FRAMES and s["tracked"] + s["not_initialized"] == s["received"], s
    poses = messages(run["first"], "/lrdslam/pose")
    assert len(poses) == s["tracked"], (len(poses), s)
    frame_stamps = {float(l.split()[0]) for l in (sequence / "rgb.txt").read_text().splitlines()
                    if l.strip() and not l.startswith("#")}
    rows = []
    for m in poses:
        h, p = m["msg"]["header"], m["msg"]["pose"]
        assert h["frame_id"] == "map"
        t = float(f"{stamp(h):.6f}")
        assert t in frame_stamps, t
        q = p["orientation"]
        assert abs(np.linalg.norm([q["x"], q["y"], q["z"], q["w"]]) - 1) < 1e-9
        rows.append(f"{t:.6f} {p['position']['x']} {p['position']['y']} {p['position']['z']} "
                    f"{q['x']} {q['y']} {q['z']} {q['w']}")
    est = run["tmp"] / "poses.txt"
    est.write_text("\n".join(rows) + "\n")
    r = lrdslam("eval", sequence / "groundtruth.txt", est, "--json", "-")
    ate = json.loads(r.stdout)["ate"]["rmse"]
    assert ate < 0.02, ate


def test_every_decoded_field_is_as_published(run):
    lines = run["first"]
    state = messages(lines, "/lrdslam/state")
    assert state and all(m["msg"]["data"] in ("ok", "not_initialized", "lost") for m in state), state
    # The last path is the saved trajectory.
    path = messages(lines, "/lrdslam/path")[-1]["msg"]
    assert path["header"]["frame_id"] == "map"
    saved = [l.split() for l in (run["out"] / "CameraTrajectory.txt").read_text().splitlines()
             if l.strip() and not l.startswith("#")]
    assert len(path["poses"]) == len(saved) == run["summary"]["tracked"]
    for pose, row in zip(path["poses"], saved):
        assert f"{stamp(pose['header']):.6f}" == row[0]
        assert abs(pose["pose"]["position"]["x"] - float(row[1])) < 1e-6
    cloud = messages(lines, "/lrdslam/map_points")[-1]["msg"]
    assert cloud["header"]["frame_id"] == "map" and cloud["height"] == 1 and cloud["width"] > 100
    assert [(f["name"], f["offset"], f["datatype"], f["count"]) for f in cloud["fields"]] == \
        [("x", 0, 7, 1), ("y", 4, 7, 1), ("z", 8, 7, 1)]
    assert cloud["point_step"] == 16 and cloud["row_step"] == 16 * cloud["width"]
    assert cloud["data"]["length"] == cloud["row_step"] and not cloud["is_bigendian"]
    grid = messages(lines, "/lrdslam/occupancy")[-1]["msg"]
    info = grid["info"]
    assert grid["header"]["frame_id"] == "map" and info["width"] > 10 and info["height"] > 10
    assert grid["data"]["length"] == info["width"] * info["height"]
    assert abs(info["resolution"] - 0.05) < 1e-6
    q = info["origin"]["orientation"]
    assert abs(np.linalg.norm([q["x"], q["y"], q["z"], q["w"]]) - 1) < 1e-9
    markers = messages(lines, "/lrdslam/keyframes")[-1]["msg"]["markers"]
    assert len(markers) == 1 and markers[0]["type"] == 5 and markers[0]["ns"] == "keyframes"
    assert len(markers[0]["points"]) % 16 == 0 and len(markers[0]["points"]) >= 16


def test_a_late_subscriber_gets_the_transient_local_topics(run):
    late = run["late"]
    assert late[-1]["until_met"], late[-1]
    assert len(messages(late, "/lrdslam/pose")) >= 10
    for topic in ("/lrdslam/path", "/lrdslam/state", "/lrdslam/map_points", "/lrdslam/occupancy"):
        assert messages(late, topic), topic


def test_the_node_is_in_the_ros_graph_with_its_endpoints(run):
    lines = run["first"]
    published = {tuple(t) for t in next(l for l in lines if "published_topics" in l)["published_topics"]}
    for topic, type_ in OUTPUTS.items():
        assert (topic, type_) in published, (topic, published)
    assert ("/tf", "tf2_msgs/msg/TFMessage") in published and ("/tf_static", "tf2_msgs/msg/TFMessage") in published
    info = messages(lines, "ros_discovery_info")[-1]["msg"]
    writer = messages(lines, "/lrdslam/pose")[0]["publisher"]
    assert info["gid"]["data"] == writer[:24] + "000001c1" + "00" * 8  # the participant's GUID, Humble's 24 bytes
    (entry,) = info["node_entities_info_seq"]
    assert entry["node_name"] == "lrdslam" and entry["node_namespace"] == "/"
    writers = {g["data"] for g in entry["writer_gid_seq"]}
    for topic in OUTPUTS:
        assert messages(lines, topic)[0]["publisher"] + "00" * 8 in writers, topic
    assert len(entry["reader_gid_seq"]) == 3  # colour, depth, camera_info


def test_malformed_input_is_dropped_counted_and_named(tmp_path):
    domain = 62
    out = tmp_path / "out"
    with Node(domain, tmp_path / "node.log", "-p", f"output_dir:={out}") as node:
        node.wait_ready()
        r = subprocess.run([PUBLISHER_BIN], capture_output=True, text=True, env=env(domain), timeout=60)
        assert r.returncode == 0, r.stderr
        time.sleep(1)
        status = node.interrupt()
    log = node.output()
    assert status == 0, log
    s = json.loads((out / "node_summary.json").read_text())
    # Two pairs each: a yuv422 colour image, a truncated one, 80x60 against a 64x48 camera_info.
    assert s["malformed"] == 6 and s["tracked"] == 0, (s, log)
    assert "encoding 'yuv422' is not a colour encoding" in log
    assert ("/camera/rgb/image_color: a publisher sends std_msgs/msg/String, expected sensor_msgs/msg/Image"
            in log), log


def test_parameters_from_a_file_and_the_command_line(tmp_path):
    params = tmp_path / "params.yaml"
    params.write_text("/**:\n  ros__parameters:\n    rgb_topic: /cam/color\n    mode: static\n"
                      "lrdslam:\n  ros__parameters:\n    depth_topic: /cam/depth\n")
    with Node(63, tmp_path / "node.log", "--params-file", params, "-p", "rgb_topic:=/cam2/color",
              "-p", f"output_dir:={tmp_path / 'out'}", "-p", "no_such:=1") as node:
        node.wait_ready()
        status = node.interrupt()
    log = node.output()
    assert status == 0, log
    assert "colour /cam2/color, depth /cam/depth" in log  # -p after the file wins
    assert "no such parameter: no_such (-p no_such)" in log
    assert json.loads((tmp_path / "out" / "node_summary.json").read_text())["received"] == 0


@pytest.mark.parametrize("args, domain, message", [
    (["-p", "queue_size:=0"], "64", "queue_size must be 1..1000, got 0"),
    (["-p", "dense:=maybe"], "64", "parameter dense (-p dense): 'maybe' is not a bool"),
    (["-p", "distro:=foxy"], "64", "distro 'foxy' is not one of humble"),
    (["--bogus"], "64", "--ros-args: unknown argument '--bogus'"),
    (["-p", "autosave:=-1.0"], "64", "autosave must be a number of seconds >= 0 (0: off), got -1"),
    ([], "500", "ROS_DOMAIN_ID '500' is not a domain id 0..232"),
])
def test_a_bad_parameter_stops_the_node_with_one_line(args, domain, message):
    r = subprocess.run([NODE_BIN, "--ros-args", *args], capture_output=True, text=True, timeout=30,
                       env={**env(64), "ROS_DOMAIN_ID": domain})
    assert r.returncode == 1, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], r.stderr
