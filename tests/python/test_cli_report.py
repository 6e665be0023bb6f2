"""The HTML report (docs/report.md): `run --report` and `lrdslam report RUN_DIR` write one page that
holds everything it shows (no network), whose data agree with the run's own files; bad run folders
stop with one line naming the file. tests/python/test_report_browser.py opens the page in Chromium."""
import base64
import json
import re
import shutil

import cv2
import numpy as np
import pytest

from cli import lrdslam, page_data, synth_input

FRAMES = 60


def summary_of(out):
    return json.loads((out / "summary.json").read_text())


@pytest.fixture(scope="module")
def dense_run(tmp_path_factory):
    d = tmp_path_factory.mktemp("report")
    synth_input("--preset", "walking_xyz", "--frames", FRAMES, "--out", d / "seq")
    r = lrdslam("run", "--sequence", d / "seq", "--mode", "geometric", "--dense", "--deterministic", "--quiet",
                "--out", d / "out", "--report")
    assert f"wrote {d / 'out' / 'report.html'}" in r.stdout
    return d


def test_the_page_holds_everything_it_shows(dense_run):
    html = (dense_run / "out" / "report.html").read_text()
    # Nothing fetched: no external script, style, image or link.
    assert not re.search(r'<(script|img|link|iframe)[^>]+(src|href)\s*=\s*["\']?(https?:|//|file:)', html, re.I)
    assert "<link" not in html and not re.search(r"<script[^>]+src=", html)
    # The data, uPlot, three.js and its orbit controls (the run has a dense map), the pages' helpers,
    # the 3-D view, the run page's script.
    assert html.count("<script") == 7
    assert "uPlot" in html and "lrdReport" in html


def test_the_page_data_agree_with_the_run(dense_run):
    out = dense_run / "out"
    data = page_data((out / "report.html").read_text())
    summary = json.loads((out / "summary.json").read_text())
    assert data["summary"] == summary
    assert summary["sequence"] == str((dense_run / "seq").resolve())

    # The per-frame rows are track_times.txt's.
    rows = [l.split() for l in (out / "track_times.txt").read_text().splitlines() if not l.startswith("#")]
    assert data["frames"]["index"] == [int(r[0]) for r in rows] and len(rows) == FRAMES
    assert data["frames"]["state"].count("ok") == summary["tracked"]
    assert data["frames"]["stages"]["geometry"] == pytest.approx([float(r[5]) for r in rows], abs=1e-3)

    # The trajectory is aligned as the ATE aligns it: its errors give the summary's RMSE, and each
    # aligned position lies that far from its ground-truth position.
    t = data["trajectory"]
    err = np.array(t["error"])
    assert len(err) == summary["ate"]["pairs"] == summary["tracked"]
    assert np.sqrt(np.mean(err ** 2)) == pytest.approx(summary["ate"]["rmse"], abs=2e-5)
    est = np.array([t["est"]["x"], t["est"]["y"], t["est"]["z"]]).T
    gt = np.array([t["gt"]["x"], t["gt"]["y"], t["gt"]["z"]]).T
    assert np.linalg.norm(est - gt, axis=1) == pytest.approx(err, abs=3e-5)
    truth = np.loadtxt(dense_run / "seq" / "groundtruth.txt")
    assert len(t["gt_path"]["x"]) == len(truth)

    # The 3-D view: the dense map's points (all of them: a short run), the sparse map's, the keyframes.
    m = data["map3d"]
    dense = np.frombuffer(base64.b64decode(m["dense"]["positions"]), np.float32).reshape(-1, 3)
    assert m["dense"]["of"] == summary["dense"]["points"] and m["dense"]["count"] == len(dense) <= 150000
    ply = (out / "dense_map.ply").read_bytes()
    body = ply[ply.index(b"end_header\n") + len(b"end_header\n"):]
    vertices = np.frombuffer(body, np.dtype([("p", "<f4", 3), ("rgb", "u1", 3)]))
    stride = -(-len(vertices) // 150000)
    assert np.array_equal(dense, vertices["p"][::stride])  # every stride-th point, at most 150,000
    assert np.array_equal(np.frombuffer(base64.b64decode(m["dense"]["colours"]), np.uint8).reshape(-1, 3),
                          vertices["rgb"][::stride])
    sparse = np.frombuffer(base64.b64decode(m["sparse"]["positions"]), np.float32).reshape(-1, 3)
    assert len(sparse) == m["sparse"]["count"] == summary["map_points"] and "colours" not in m["sparse"]
    keyframes = np.loadtxt(out / "KeyFrameTrajectory.txt", ndmin=2)
    assert len(m["keyframes"]["x"]) == summary["keyframes"] == len(keyframes)
    assert m["keyframes"]["z"] == pytest.approx(keyframes[:, 3], abs=1e-5)

    # The maps the run drew, as they are on disk.
    files = {i["file"]: i for i in data["images"]}
    assert set(files) == {"dense_map.png", "occupancy_2d.png"}
    for name, image in files.items():
        prefix = "data:image/png;base64,"
        assert image["src"].startswith(prefix)
        decoded = cv2.imdecode(np.frombuffer(base64.b64decode(image["src"][len(prefix):]), np.uint8), cv2.IMREAD_COLOR)
        assert np.array_equal(decoded, cv2.imread(str(out / name), cv2.IMREAD_COLOR)), name


def test_run_report_draws_the_sample_frames_it_chose(dense_run):
    out = dense_run / "out"
    index = json.loads((out / "report_frames" / "frames.json").read_text())["frames"]
    rows = {int(r[0]): r for r in (l.split() for l in (out / "track_times.txt").read_text().splitlines()
                                   if not l.startswith("#"))}
    assert 0 < len(index) <= 24
    chosen = {}
    for f in index:
        for why in f["reasons"]:
            chosen.setdefault(why, []).append(f)
        assert f["removed"] == int(rows[f["frame"]][14]) and f["mask_age"] == int(rows[f["frame"]][13])
    # The most keypoints removed by the geometry check: the run's eight largest counts.
    removed = sorted((int(r[14]) for r in rows.values()), reverse=True)[:8]
    assert sorted((f["removed"] for f in chosen["most keypoints removed"]), reverse=True) == removed
    # `geometric` mode uses no masks: no frame for the oldest mask.
    assert "oldest mask" not in chosen
    # The largest errors are errors of the trajectory as the report aligns it, largest first among
    # those kept.
    data = page_data((out / "report.html").read_text())
    by_stamp = {round(t, 4): e for t, e in zip(data["trajectory"]["t"], data["trajectory"]["error"])}
    assert len(chosen["largest error"]) == 8
    for f in chosen["largest error"]:
        assert f["error"] == pytest.approx(by_stamp[round(f["timestamp"], 4)], abs=2e-5)
    # The dynamic flags of each scored frame add up to the summary's.
    flags, totals = data["flags"], summary_of(out)["dynamic_flags"]
    assert len(flags["frame"]) == totals["frames"] > 0
    for key in ("true_positive", "false_positive", "false_negative"):
        assert sum(flags[key]) == totals[key], key
    # Y, timed on the pool's frames after the run, for the times on the page.
    assert data["yardstick"]["frames"] > 0 and data["yardstick"]["ms"] > 0
    # The page shows each as drawn: the mask tinted, keypoints in two colours.
    assert [s["frame"] for s in data["samples"]] == [f["frame"] for f in index]
    for s in data["samples"]:
        jpeg = (out / "report_frames" / s["file"]).read_bytes()
        assert base64.b64decode(s["src"][len("data:image/jpeg;base64,"):]) == jpeg
    most = max(index, key=lambda f: f["removed"])
    img = cv2.imread(str(out / "report_frames" / most["file"]), cv2.IMREAD_COLOR)
    magenta = (img[:, :, 0] > 170) & (img[:, :, 2] > 170) & (img[:, :, 1] < 110)
    green = (img[:, :, 1] > 150) & (img[:, :, 0] < 120) & (img[:, :, 2] < 120)
    assert np.count_nonzero(magenta) > 10 * most["removed"] and np.count_nonzero(green) > 0


def test_run_report_shows_the_repairs_of_the_keyframes_with_the_most_dynamic_pixels(dense_run):
    out = dense_run / "out"
    repairs = json.loads((out / "report_frames" / "frames.json").read_text())["repairs"]
    summary = json.loads((out / "summary.json").read_text())
    assert 0 < len(repairs) <= min(6, summary["dense"]["repair"]["keyframes"])
    dynamic = [r["dynamic_pixels"] for r in repairs]
    assert dynamic == sorted(dynamic, reverse=True) and all(0 < r["filled_pixels"] <= r["dynamic_pixels"] for r in repairs)
    assert sum(dynamic) <= summary["dense"]["repair"]["dynamic_pixels"]
    data = page_data((out / "report.html").read_text())
    assert [r["file"] for r in data["repairs"]] == [r["file"] for r in repairs]
    # Colour before | after on top, depth below, at half size: the repair changed the colour.
    img = cv2.imread(str(out / "report_frames" / repairs[0]["file"]), cv2.IMREAD_COLOR)
    assert img.shape == (480, 640, 3)
    before, after = img[:240, :320].astype(int), img[:240, 320:].astype(int)
    assert np.mean(np.abs(before - after).sum(axis=2) > 60) > 0.02


def test_the_report_command_writes_the_same_page_elsewhere_and_without_ground_truth(dense_run, tmp_path):
    out = dense_run / "out"
    lrdslam("report", out, "--out", tmp_path / "again.html")
    assert page_data((tmp_path / "again.html").read_text()) == page_data((out / "report.html").read_text())

    # A copy of the run whose sequence is gone: the trajectory in its own frame, no errors.
    copy = tmp_path / "run"
    shutil.copytree(out, copy)
    summary = json.loads((copy / "summary.json").read_text())
    summary["sequence"] = str(tmp_path / "gone")
    (copy / "summary.json").write_text(json.dumps(summary))
    lrdslam("report", copy)
    data = page_data((copy / "report.html").read_text())
    assert "error" not in data["trajectory"] and data["ground_truth"] == ""
    assert len(data["trajectory"]["t"]) == summary["tracked"]
    # --sequence names the ground truth again.
    lrdslam("report", copy, "--sequence", dense_run / "seq")
    assert len(page_data((copy / "report.html").read_text())["trajectory"]["error"]) == summary["tracked"]


@pytest.mark.parametrize("case", ["no_summary", "bad_summary", "bad_times", "bad_sequence", "bad_truth"])
def test_bad_run_folders_stop_with_one_line(dense_run, tmp_path, case):
    run = tmp_path / "run"
    shutil.copytree(dense_run / "out", run)
    (run / "report.html").unlink()
    extra = []
    if case == "no_summary":
        (run / "summary.json").unlink()
        expected = f"{run / 'summary.json'}: cannot read"
    elif case == "bad_summary":
        (run / "summary.json").write_text("{ not json")
        expected = f"{run / 'summary.json'}: not valid JSON"
    elif case == "bad_times":
        lines = (run / "track_times.txt").read_text().splitlines()
        lines[5] = lines[5].rsplit(" ", 2)[0]
        (run / "track_times.txt").write_text("\n".join(lines) + "\n")
        expected = f"{run / 'track_times.txt'}:6: expected 15 fields, got 13"
    elif case == "bad_sequence":
        extra = ["--sequence", run / "summary.json"]
        expected = f"{run / 'summary.json'}: not a sequence folder"
    else:
        seq = tmp_path / "seq"
        seq.mkdir()
        (seq / "groundtruth.txt").write_text("1.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n")
        extra = ["--sequence", seq]
        expected = f"{seq / 'groundtruth.txt'}"
    r = lrdslam("report", run, *extra, check=False)
    assert r.returncode == 1
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and expected in lines[0], r.stderr
    assert not (run / "report.html").exists()
