"""ROS 2 bags against an implementation that is not ours (Foxglove's @mcap/core and
@foxglove/rosmsg2-serialization with the official message definitions, tests/ros2/peer_bags.cjs):
a bag they write from a TUM folder's frames runs exactly as the folder does, and every message of a
bag we write decodes there with the right counts, frame ids, sizes and stamps. Skips when Node.js or
the packages (scripts/fetch-ros2-test-peers.sh) are absent."""
import json
import os
import shutil
import subprocess
from pathlib import Path

import cv2
import numpy as np
import pytest
import yaml

from cli import run_bag_and_folder, synth_input

ROOT = Path(__file__).resolve().parents[2]
MODULES = ROOT / "data" / "npm-ros2" / "node_modules"
SCRIPT = ROOT / "tests" / "ros2" / "peer_bags.cjs"
FRAMES = 40

pytestmark = pytest.mark.skipif(
    shutil.which("node") is None or not (MODULES / "@mcap" / "core").is_dir()
    or not (MODULES / "@foxglove" / "rosmsg2-serialization").is_dir(),
    reason="needs node and the npm packages scripts/fetch-ros2-test-peers.sh fetches into data/npm-ros2")


def _node(*args):
    r = subprocess.run(["node", SCRIPT, *map(str, args)], capture_output=True, text=True,
                       env={**os.environ, "NODE_PATH": str(MODULES)})
    assert r.returncode == 0, r.stderr
    return r.stdout


@pytest.fixture(scope="module")
def sequence(tmp_path_factory):
    d = tmp_path_factory.mktemp("peers")
    synth_input("--preset", "walking_xyz", "--frames", FRAMES, "--out", d / "seq", "--bag", d / "ours.mcap")
    return d


def _list(path):
    return [l.split() for l in path.read_text().splitlines() if l.strip() and not l.startswith("#")]


def _raw_frames(folder, out):
    """The folder's frames as raw rgb8 and 32FC1 bytes (Node has no PNG decoder), the depth in metres
    exactly as lrd-slam computes it (the PNG value / DepthMapFactor in double, then float)."""
    settings = yaml.safe_load((folder / "settings.yaml").read_text().split("\n", 1)[1].replace("!!opencv-matrix", ""))
    factor = float(settings["DepthMapFactor"])
    rgb, depth = _list(folder / "rgb.txt"), _list(folder / "depth.txt")
    assert len(rgb) == len(depth) == FRAMES
    frames = []
    for k, ((ts, rgb_file), (td, depth_file)) in enumerate(zip(rgb, depth)):
        colour = cv2.imread(str(folder / rgb_file), cv2.IMREAD_COLOR)
        (out / f"{k}.rgb").write_bytes(cv2.cvtColor(colour, cv2.COLOR_BGR2RGB).tobytes())
        raw = cv2.imread(str(folder / depth_file), cv2.IMREAD_UNCHANGED)
        (out / f"{k}.depth").write_bytes((raw.astype(np.float64) / factor).astype("<f4").tobytes())
        frames.append({"rgb_stamp": ts, "depth_stamp": td, "rgb": f"{k}.rgb", "depth": f"{k}.depth"})
    gt = [{"stamp": row[0], "t": list(map(float, row[1:4])), "q": list(map(float, row[4:8]))}
          for row in _list(folder / "groundtruth.txt")]
    camera = {"width": int(settings["Camera.width"]), "height": int(settings["Camera.height"]),
              "fx": float(settings["Camera.fx"]), "fy": float(settings["Camera.fy"]),
              "cx": float(settings["Camera.cx"]), "cy": float(settings["Camera.cy"]),
              "d": [float(settings.get(k, 0.0)) for k in ("Camera.k1", "Camera.k2", "Camera.p1", "Camera.p2", "Camera.k3")]}
    (out / "frames.json").write_text(json.dumps({"camera": camera, "frames": frames, "groundtruth": gt}))
    return camera, frames


def test_a_bag_written_by_mcap_core_runs_as_its_folder(sequence, tmp_path):
    folder = sequence / "seq"
    (tmp_path / "raw").mkdir()
    _raw_frames(folder, tmp_path / "raw")
    peer = tmp_path / "peer.mcap"
    _node("write", tmp_path / "raw", peer)
    run_bag_and_folder(folder, peer, tmp_path, FRAMES, "--deterministic", "--quiet")


def test_every_message_of_our_bag_decodes_with_the_official_definitions(sequence, tmp_path):
    (tmp_path / "raw").mkdir()
    camera, frames = _raw_frames(sequence / "seq", tmp_path / "raw")
    s = json.loads(_node("read", sequence / "ours.mcap"))
    assert s["profile"] == "ros2"
    assert s["schemasMatchOfficial"]
    assert s["chunkCompressions"] == ["zstd"]
    assert s["statistics"]["messageCount"] == 5 * FRAMES and s["statistics"]["channelCount"] == 5
    t = s["topics"]
    expected = {"/camera/rgb/image_color": ("sensor_msgs/msg/Image", "/openni_rgb_optical_frame"),
                "/camera/depth/image": ("sensor_msgs/msg/Image", "/openni_depth_optical_frame"),
                "/camera/rgb/camera_info": ("sensor_msgs/msg/CameraInfo", "/openni_rgb_optical_frame"),
                "/camera/depth/camera_info": ("sensor_msgs/msg/CameraInfo", "/openni_depth_optical_frame"),
                "/tf": ("tf2_msgs/msg/TFMessage", "/world")}
    assert set(t) == set(expected)
    for topic, (type_name, frame_id) in expected.items():
        assert (t[topic]["type"], t[topic]["encoding"], t[topic]["schemaEncoding"]) == (type_name, "cdr", "ros2msg")
        assert t[topic]["count"] == FRAMES, topic
        assert t[topic]["frameIds"] == [frame_id], topic
    w, h = camera["width"], camera["height"]
    rgb, depth = t["/camera/rgb/image_color"], t["/camera/depth/image"]
    assert rgb["sizes"] == [[w, h]] * FRAMES and depth["sizes"] == [[w, h]] * FRAMES
    assert set(rgb["encodings"]) == {"rgb8"} and set(depth["encodings"]) == {"32FC1"}
    assert rgb["dataBytes"] == [w * h * 3] * FRAMES and depth["dataBytes"] == [w * h * 4] * FRAMES
    # Stamps: the folder's six-decimal stamps exactly, in order.
    assert rgb["stamps"] == [f["rgb_stamp"] + "000" for f in frames]
    assert depth["stamps"] == [f["depth_stamp"] + "000" for f in frames]
    info = t["/camera/rgb/camera_info"]["camera"]
    assert info["k"] == [camera["fx"], 0, camera["cx"], 0, camera["fy"], camera["cy"], 0, 0, 1]
    assert info["distortion_model"] == "plumb_bob" and len(info["d"]) == 5
    assert t["/tf"]["childFrameIds"] == ["/kinect"]
