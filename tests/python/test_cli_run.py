"""`lrdslam run` end to end: outputs, accuracy on a static synthetic sequence, byte-identical
deterministic runs, and one-line errors for bad input."""
import json

import pytest

from cli import lrdslam, synth_input

FRAMES = 90


@pytest.fixture(scope="module")
def sequence(tmp_path_factory):
    d = tmp_path_factory.mktemp("seq") / "static_xyz"
    synth_input("--preset", "static_xyz", "--frames", FRAMES, "--out", d)
    return d


def test_run_writes_outputs_and_is_accurate(sequence, tmp_path):
    out = tmp_path / "out"
    r = lrdslam("run", "--sequence", sequence, "--out", out, "--quiet")
    assert "ATE RMSE" in r.stdout
    for name in ["CameraTrajectory.txt", "KeyFrameTrajectory.txt", "track_times.txt", "summary.json"]:
        assert (out / name).is_file(), name
    summary = json.loads((out / "summary.json").read_text())
    assert summary["frames"] == FRAMES
    assert summary["lost"] == 0
    assert summary["ate"]["rmse"] < 0.01
    assert summary["keyframes"] >= 1 and summary["map_points"] > 100
    rows = [l.split() for l in (out / "track_times.txt").read_text().splitlines() if not l.startswith("#")]
    assert len(rows) == FRAMES
    assert all(len(row) == 15 and row[10] == "ok" for row in rows)
    poses = [l for l in (out / "CameraTrajectory.txt").read_text().splitlines() if not l.startswith("#")]
    assert len(poses) == FRAMES


def test_deterministic_runs_are_byte_identical(sequence, tmp_path):
    outs = []
    for k in range(2):
        out = tmp_path / f"run{k}"
        lrdslam("run", "--sequence", sequence, "--out", out, "--deterministic", "--quiet")
        outs.append(out)
    for name in ["CameraTrajectory.txt", "KeyFrameTrajectory.txt"]:
        assert (outs[0] / name).read_bytes() == (outs[1] / name).read_bytes(), name


def test_preload_changes_timing_only(sequence, tmp_path):
    # --preload decodes every frame first; in deterministic mode the trajectory is the same bytes.
    outs = []
    for k, extra in enumerate([[], ["--preload"]]):
        out = tmp_path / f"run{k}"
        lrdslam("run", "--sequence", sequence, "--out", out, "--deterministic", "--quiet", *extra)
        outs.append(out)
    assert (outs[0] / "CameraTrajectory.txt").read_bytes() == (outs[1] / "CameraTrajectory.txt").read_bytes()


@pytest.mark.parametrize(
    "args, expected",
    [
        (["--sequence", "/nonexistent/seq"], "/nonexistent/seq"),
        (["--preset", "tum9"], "tum9"),
    ],
)
def test_bad_input_gives_one_line_error(sequence, tmp_path, args, expected):
    full = ["run", "--out", tmp_path / "o", "--quiet"]
    if "--sequence" not in args:
        full += ["--sequence", sequence]
    r = lrdslam(*full, *args, check=False)
    assert r.returncode != 0
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:") and expected in lines[0], r.stderr


def test_settings_and_preset_exclude_each_other(sequence, tmp_path):
    r = lrdslam("run", "--sequence", sequence, "--out", tmp_path / "o", "--settings",
                sequence / "settings.yaml", "--preset", "tum1", check=False)
    assert r.returncode != 0


def test_realtime_feeds_frames_at_the_cameras_pace(sequence, tmp_path):
    """--realtime: frame k is not tracked before k / fps after the first, like a live camera."""
    lrdslam("run", "--sequence", sequence, "--out", tmp_path, "--quiet", "--realtime", "--max-frames", 45)
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["frames"] == 45
    assert s["wall_seconds"] >= 44 / 30.0 - 0.01  # 45 frames at 30 Hz span 1.47 s


def test_summary_reports_place_recognition(sequence, tmp_path):
    on = tmp_path / "on"
    r = lrdslam("run", "--sequence", sequence, "--out", on, "--quiet", "--max-frames", 30)
    assert "loop closing on" in r.stdout
    s = json.loads((on / "summary.json").read_text())
    assert s["loop_closing"] is True
    assert s["vocabulary"].endswith("orb_vocab.lrdv")
    assert s["loops"] == [] and s["relocalizations"] == 0  # 30 frames of a static sweep: nothing to close
    assert s["rejected_loops"] == 0
    off = tmp_path / "off"
    r = lrdslam("run", "--sequence", sequence, "--out", off, "--quiet", "--max-frames", 30, "--no-loop-closing")
    assert "loop closing off" in r.stdout
    assert json.loads((off / "summary.json").read_text())["loop_closing"] is False


def test_corrupt_vocabulary_is_a_one_line_error(sequence, tmp_path):
    bad = tmp_path / "bad.lrdv"
    bad.write_bytes(b"not a vocabulary at all")
    r = lrdslam("run", "--sequence", sequence, "--out", tmp_path / "o", "--quiet", "--vocabulary", bad, check=False)
    assert r.returncode != 0
    lines = [l for l in r.stderr.splitlines() if l.startswith("error")]
    assert len(lines) == 1 and str(bad) in lines[0]


def test_a_bonn_folder_gets_bonns_calibration_from_its_name(sequence, tmp_path):
    # A Bonn RGB-D Dynamic download: the TUM layout without our settings.yaml, named rgbd_bonn_*.
    bonn = tmp_path / "rgbd_bonn_static"
    bonn.mkdir()
    for name in ["rgb", "depth"]:
        (bonn / name).symlink_to(sequence / name)
    for name in ["rgb.txt", "depth.txt", "groundtruth.txt"]:
        (bonn / name).write_bytes((sequence / name).read_bytes())
    out = tmp_path / "out"
    lrdslam("run", "--sequence", bonn, "--out", out, "--max-frames", 5, "--quiet")
    summary = json.loads((out / "summary.json").read_text())
    assert summary["camera"] == "preset bonn (from the folder name)"
    assert summary["frames"] == 5
