"""`lrdslam run --synth PRESET`: frames rendered on the fly (the long runs of
bench/results/scale.md). The streamed run equals the run over the folder `lrdslam synth` writes,
byte for byte in deterministic mode; it writes nothing but its outputs and its ground truth; bad
options are one-line errors."""
import json

import pytest

from cli import lrdslam, page_data, synth_input

FRAMES = 40
SEED = 4


@pytest.fixture(scope="module")
def written_and_streamed(tmp_path_factory):
    root = tmp_path_factory.mktemp("synth_stream")
    seq = root / "walking_xyz"
    # Rendered by the release build when there is one (cli.synth_input), streamed by the binary under
    # test: the frames must be the same bytes whatever the optimization.
    synth_input("--preset", "walking_xyz", "--frames", FRAMES, "--seed", SEED, "--out", seq)
    common = ["--mode", "static", "--deterministic", "--quiet"]
    lrdslam("run", "--sequence", seq, "--out", root / "from_folder", *common)
    r = lrdslam("run", "--synth", "walking_xyz", "--seed", SEED, "--frames", FRAMES, "--out", root / "streamed",
                *common)
    return seq, root / "from_folder", root / "streamed", r


def test_a_streamed_run_equals_the_run_over_the_written_folder(written_and_streamed):
    seq, from_folder, streamed, _ = written_and_streamed
    for name in ["CameraTrajectory.txt", "KeyFrameTrajectory.txt"]:
        assert (streamed / name).read_bytes() == (from_folder / name).read_bytes(), name
    assert (streamed / "groundtruth.txt").read_text().splitlines()[-FRAMES:] == \
        (seq / "groundtruth.txt").read_text().splitlines()[-FRAMES:]
    a = json.loads((streamed / "summary.json").read_text())
    b = json.loads((from_folder / "summary.json").read_text())
    assert a["frames"] == b["frames"] == FRAMES
    # The same estimate; the folder's ground truth is the rendered poses printed to 4 decimals.
    assert abs(a["ate"]["rmse"] - b["ate"]["rmse"]) < 1e-6
    assert a["ate"]["rmse"] < 0.15  # static mode (ORB-SLAM2) among walkers
    assert a["sequence"] == f"synth:walking_xyz?seed={SEED}&session=1&frames={FRAMES}"


def test_a_streamed_run_writes_only_its_outputs(written_and_streamed):
    _, _, streamed, r = written_and_streamed
    names = sorted(p.name for p in streamed.iterdir())
    assert names == ["CameraTrajectory.txt", "KeyFrameTrajectory.txt", "groundtruth.txt", "summary.json",
                     "track_times.txt"], names
    assert "camera: the synthetic camera of synth:walking_xyz" in r.stdout
    assert "ATE RMSE" in r.stdout


def test_the_report_of_a_streamed_run_reads_its_ground_truth(written_and_streamed):
    _, _, streamed, _ = written_and_streamed
    lrdslam("report", streamed)
    data = page_data((streamed / "report.html").read_text())
    assert data["ground_truth"] == str(streamed / "groundtruth.txt")
    assert data["trajectory"]["frame"] == "ground truth (world)"
    assert len(data["trajectory"]["t"]) == FRAMES
    assert max(data["trajectory"]["error"]) < 0.3  # static mode among walkers


@pytest.mark.parametrize(
    "args, expected",
    [
        (["--synth", "no_such_preset"], "no_such_preset"),
        (["--seed", "3", "--sequence", "/tmp"], "--seed"),
        (["--synth", "walking_xyz", "--frames", "0"], "--frames"),
        (["--synth", "walking_xyz", "--session", "9"], "--session"),
        (["--synth", "walking_xyz", "--sequence", "/tmp"], "--sequence"),
        ([], "--synth PRESET"),
    ],
)
def test_bad_synth_options_are_one_line_errors(tmp_path, args, expected):
    r = lrdslam("run", "--out", tmp_path / "o", "--quiet", *args, check=False)
    assert r.returncode != 0
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and expected in lines[0], r.stderr
    assert not (tmp_path / "o" / "CameraTrajectory.txt").exists()
