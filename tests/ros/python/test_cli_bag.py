"""`lrdslam synth --bag` and `lrdslam run --bag` (README, "On a robot with ROS"): a synthetic
sequence written as a TUM-style bag runs exactly as its folder does, with every output a folder run
has."""
import json
import subprocess

import pytest

from cli import lrdslam, run_bag_and_folder

FRAMES = 80


@pytest.fixture(scope="module")
def sequence(tmp_path_factory):
    d = tmp_path_factory.mktemp("bagseq")
    lrdslam("synth", "--preset", "walking_xyz", "--frames", FRAMES, "--out", d / "seq", "--bag", d / "seq.bag")
    return d / "seq", d / "seq.bag"


def test_the_bag_has_the_tum_topics_types_and_ground_truth(sequence):
    _, bag = sequence
    info = subprocess.run(["rosbag", "info", "--yaml", str(bag)], capture_output=True, text=True, check=True)
    topics = {t["topic"]: (t["type"], t["messages"]) for t in _yaml(info.stdout)["topics"]}
    assert topics["/camera/rgb/image_color"] == ("sensor_msgs/Image", FRAMES)
    assert topics["/camera/depth/image"] == ("sensor_msgs/Image", FRAMES)
    assert topics["/camera/rgb/camera_info"] == ("sensor_msgs/CameraInfo", FRAMES)
    assert topics["/camera/depth/camera_info"] == ("sensor_msgs/CameraInfo", FRAMES)
    assert topics["/tf"] == ("tf2_msgs/TFMessage", FRAMES)


def test_a_bag_and_its_folder_give_the_same_trajectory_bit_for_bit(sequence, tmp_path):
    folder, bag = sequence
    common = ["--deterministic", "--mode", "full", "--segmenter", "fnet", "--quiet"]
    sb = run_bag_and_folder(folder, bag, tmp_path, FRAMES, *common)
    assert sb["ate"]["rmse"] < 0.02
    assert sb["frames"] == FRAMES


def test_a_bag_run_writes_the_dense_map_and_keyframes(sequence, tmp_path):
    _, bag = sequence
    lrdslam("run", "--bag", bag, "--mode", "static", "--dense", "--max-frames", 40, "--quiet", "--out", tmp_path)
    for f in ("CameraTrajectory.txt", "KeyFrameTrajectory.txt", "summary.json", "dense_map.ply", "dense_map.png"):
        assert (tmp_path / f).stat().st_size > 0, f
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["frames"] == 40
    assert "ate" not in summary  # no --gt-from-tf: no ground truth


@pytest.mark.parametrize(
    "args, message",
    [
        (["--rgb-topic", "/nope"], "topic /nope not found; the bag has /camera/depth/camera_info"),
        (["--depth-topic", "/camera/rgb/camera_info"],
         "topic /camera/rgb/camera_info carries sensor_msgs/CameraInfo, expected sensor_msgs/Image"),
        (["--gt-from-tf", "/world:/nowhere"], "no transform from /world to /nowhere on /tf"),
        (["--gt-from-tf", "world"], "--gt-from-tf expects PARENT:CHILD"),
    ],
)
def test_bad_bag_options_stop_with_one_line_naming_the_bag_and_topic(sequence, tmp_path, args, message):
    _, bag = sequence
    r = lrdslam("run", "--bag", bag, "--out", tmp_path, *args, check=False)
    assert r.returncode != 0
    assert message in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


def test_frames_come_from_a_folder_or_a_bag_not_both(sequence, tmp_path):
    folder, bag = sequence
    r = lrdslam("run", "--out", tmp_path, check=False)
    assert r.returncode != 0 and "give the frames as --sequence FOLDER, --bag FILE.bag or --synth PRESET" in r.stderr
    r = lrdslam("run", "--sequence", folder, "--bag", bag, "--out", tmp_path, check=False)
    assert r.returncode != 0 and "excludes" in r.stderr


def _yaml(text):
    import yaml

    return yaml.safe_load(text)
