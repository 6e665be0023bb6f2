"""The benchmark page (docs/report.md): `lrdslam report BENCH_DIR` on a folder bench_dynamic wrote
(results.json, runs/PRESET/MODE/) shows the results and, per preset, every mode's trajectory aligned
onto the ground truth; bench_dynamic writes the same page as report.html. Bad folders stop with one
line naming the file."""
import json
import re
import shutil

import numpy as np
import pytest

from benchmark_folder import MODES, PRESETS
from cli import lrdslam, page_data


@pytest.fixture(scope="module")
def bench(benchmark_folder):
    bench = benchmark_folder
    r = lrdslam("report", bench)
    assert f"wrote {bench / 'report.html'}" in r.stdout
    return bench


def test_the_benchmark_page_holds_the_results_and_every_modes_trajectory(bench):
    html = (bench / "report.html").read_text()
    assert f"<title>lrd-slam benchmark: {bench.name}</title>" in html
    assert "<link" not in html and not re.search(r"<script[^>]+src=", html)
    data = page_data(html)
    results = json.loads((bench / "results.json").read_text())
    assert data["kind"] == "benchmark" and data["results"] == results
    assert data["presets"] == list(PRESETS) and data["modes"] == MODES
    assert set(data["trajectories"]) == set(PRESETS)
    for preset, frames in PRESETS.items():
        plot = data["trajectories"][preset]
        truth = np.loadtxt(bench.parent / "sequences" / preset / "groundtruth.txt")
        assert len(plot["gt_path"]["x"]) == len(truth)
        assert plot["gt_path"]["x"] == pytest.approx(truth[:, 1], abs=1e-5)
        assert set(plot["modes"]) == set(MODES) and plot["notes"] == []
        for mode in MODES:
            # Each mode aligned as its ATE: the errors give the run's RMSE, one per associated pose.
            summary = json.loads((bench / "runs" / preset / mode / "summary.json").read_text())
            t = plot["modes"][mode]
            err = np.array(t["error"])
            assert len(err) == summary["ate"]["pairs"] and len(t["est"]["x"]) == len(err)
            assert np.sqrt(np.mean(err ** 2)) == pytest.approx(summary["ate"]["rmse"], abs=2e-5)
            # Each aligned position lies its error away from the ground truth nearest in time (the
            # pose the ATE associated).
            gt = truth[[int(np.argmin(np.abs(truth[:, 0] - s))) for s in t["t"]], 1:4]
            est = np.array([t["est"]["x"], t["est"]["y"], t["est"]["z"]]).T
            assert np.linalg.norm(est - gt, axis=1) == pytest.approx(err, abs=3e-5)


def test_a_run_without_trajectory_or_truth_is_a_note_not_an_error(bench, tmp_path):
    copy = tmp_path / "bench"
    shutil.copytree(bench, copy)
    (copy / "report.html").unlink()
    (copy / "runs" / "static_xyz" / "geometric" / "CameraTrajectory.txt").unlink()
    summary_file = copy / "runs" / "walking_xyz" / "static" / "summary.json"
    summary = json.loads(summary_file.read_text())
    summary["sequence"] = str(tmp_path / "gone")
    summary_file.write_text(json.dumps(summary))
    lrdslam("report", copy)
    data = page_data((copy / "report.html").read_text())
    assert set(data["trajectories"]["static_xyz"]["modes"]) == {"static"}
    assert data["trajectories"]["static_xyz"]["notes"] == [f"geometric: no {copy / 'runs/static_xyz/geometric/CameraTrajectory.txt'}"]
    assert set(data["trajectories"]["walking_xyz"]["modes"]) == {"geometric"}
    assert data["trajectories"]["walking_xyz"]["notes"] == [f"static: no ground truth for {copy / 'runs/walking_xyz/static'}"]


@pytest.mark.parametrize("case", ["bad_json", "no_runs", "no_mode", "bad_trajectory", "sequence_flag"])
def test_bad_benchmark_folders_stop_with_one_line(bench, tmp_path, case):
    copy = tmp_path / "bench"
    shutil.copytree(bench, copy)
    (copy / "report.html").unlink()
    results = copy / "results.json"
    extra = []
    if case == "bad_json":
        results.write_text('{"runs": [')
        expected = f"{results}: not valid JSON"
    elif case == "no_runs":
        results.write_text('{"segmenter": "none"}')
        expected = f'{results}: not a benchmark\'s results (no "runs" list)'
    elif case == "no_mode":
        data = json.loads(results.read_text())
        del data["runs"][1]["mode"]
        results.write_text(json.dumps(data))
        expected = f'{results}: a run without a "mode" string'
    elif case == "bad_trajectory":
        trajectory = copy / "runs" / "walking_xyz" / "geometric" / "CameraTrajectory.txt"
        trajectory.write_text("1.0 0 0 zero 0 0 0 1\n")
        expected = f"{trajectory}"
    else:
        extra = ["--sequence", copy]
        expected = "--sequence is for a run's folder"
    r = lrdslam("report", copy, *extra, check=False)
    assert r.returncode == 1
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and expected in lines[0], r.stderr
    assert not (copy / "report.html").exists()
