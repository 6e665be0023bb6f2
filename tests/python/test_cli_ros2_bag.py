"""ROS 2 bags in `lrdslam synth --bag` and `lrdslam run --bag`: a synthetic walking sequence written
as MCAP and as sqlite3 runs exactly as its folder does (and as its ROS 1 bag, in a build with ROS 1),
and broken bags stop with one line naming the file."""
import json

import pytest

from cli import lrdslam, synth_input

FRAMES = 40
PRESET = "walking_xyz"


@pytest.fixture(scope="module")
def bags(tmp_path_factory):
    d = tmp_path_factory.mktemp("ros2bag")
    # The same preset, seed and length render the same frames: one folder per bag written.
    synth_input("--preset", PRESET, "--frames", FRAMES, "--out", d / "seq", "--bag", d / "seq.mcap")
    synth_input("--preset", PRESET, "--frames", FRAMES, "--out", d / "seq2", "--bag", d / "db" / "seq.db3")
    return d


def _run(source_args, out):
    lrdslam("run", *source_args, "--out", out, "--deterministic", "--quiet")
    return (out / "CameraTrajectory.txt").read_bytes(), json.loads((out / "summary.json").read_text())


def test_synth_writes_an_mcap_file_and_a_rosbag2_sqlite_folder(bags):
    assert (bags / "seq.mcap").read_bytes()[:8] == b"\x89MCAP0\r\n"
    assert (bags / "seq.mcap").read_bytes()[-8:] == b"\x89MCAP0\r\n"
    assert (bags / "db" / "seq.db3").read_bytes()[:16] == b"SQLite format 3\x00"
    metadata = (bags / "db" / "metadata.yaml").read_text()
    assert "storage_identifier: sqlite3" in metadata
    assert f"message_count: {5 * FRAMES}\n" in metadata  # colour, depth, 2 camera_info, /tf per frame
    assert not list(bags.rglob("*.partial"))


def test_ros2_bags_give_the_folders_trajectory_bit_for_bit(bags, tmp_path):
    folder, summary = _run(["--sequence", bags / "seq"], tmp_path / "folder")
    assert len(folder.splitlines()) == FRAMES + 1
    gt = ["--gt-from-tf", "/world:/kinect"]
    for name, args in [("mcap", ["--bag", bags / "seq.mcap", *gt]), ("db3", ["--bag", bags / "db" / "seq.db3", *gt]),
                       ("db3-folder", ["--bag", bags / "db", *gt])]:
        trajectory, s = _run(args, tmp_path / name)
        assert trajectory == folder, name
        assert s["frames"] == FRAMES
        assert s["ate"]["rmse"] == summary["ate"]["rmse"], name


def test_the_ros1_bag_of_the_same_frames_gives_the_same_trajectory(bags, tmp_path):
    r = lrdslam("synth", "--preset", PRESET, "--frames", FRAMES, "--out", tmp_path / "seq", "--bag",
                tmp_path / "seq.bag", check=False)
    if r.returncode != 0:
        assert "built without ROS 1" in r.stderr, r.stderr
        pytest.skip("this lrdslam was built without ROS 1")
    ros1, _ = _run(["--bag", tmp_path / "seq.bag"], tmp_path / "ros1")
    ros2, _ = _run(["--bag", bags / "seq.mcap"], tmp_path / "ros2")
    assert ros1 == ros2


def _one_line_error(args, expected):
    r = lrdslam("run", *args, "--quiet", check=False)
    assert r.returncode == 1, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and all(e in lines[0] for e in expected), r.stderr


def test_broken_ros2_bags_stop_with_one_line_naming_the_file(bags, tmp_path):
    data = (bags / "seq.mcap").read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[: len(data) // 2])
    _one_line_error(["--bag", cut, "--out", tmp_path / "o"], [str(cut), "truncated MCAP file"])
    db = (bags / "db" / "seq.db3").read_bytes()
    cut_db = tmp_path / "cut.db3"
    cut_db.write_bytes(db[: len(db) // 3])
    _one_line_error(["--bag", cut_db, "--out", tmp_path / "o"], [str(cut_db), "truncated SQLite database"])
    _one_line_error(["--bag", bags / "seq.mcap", "--rgb-topic", "/camera/rgb/camera_info", "--out", tmp_path / "o"],
                    ["topic /camera/rgb/camera_info carries sensor_msgs/msg/CameraInfo, expected sensor_msgs/msg/Image"])
    _one_line_error(["--bag", bags / "seq.mcap", "--gt-from-tf", "/world:/nowhere", "--out", tmp_path / "o"],
                    ["no transform from /world to /nowhere on /tf"])
