"""`lrdslam run --dense` (docs/dense-map.md) on a short synthetic walking sequence in full mode: the
people's pixels in the keyframes are repaired with the static scene's depth, the dense map has no
ghosts of people and covers what the camera saw (judged against scene.ply), `eval-map` agrees with
the run, the PLY is readable, and the dense map is byte-identical in deterministic mode. The same
run writes the occupancy map and 2-D grid (docs/occupancy.md): OctoMap and map_server files, judged
against the scene (precision, recall, no people on the grid along their paths)."""
import json
import re
import shutil
import subprocess

import cv2
import numpy as np
import pytest
import yaml

from cli import lrdslam, synth_input


@pytest.fixture(scope="module")
def walking(tmp_path_factory):
    d = tmp_path_factory.mktemp("seq") / "walking_xyz"
    synth_input("--preset", "walking_xyz", "--frames", 240, "--out", d)
    return d


@pytest.fixture(scope="module")
def dense_run(walking, tmp_path_factory):
    out = tmp_path_factory.mktemp("dense")
    r = lrdslam("run", "--sequence", walking, "--out", out / "run", "--quiet", "--deterministic",
                "--mode", "full", "--segmenter", "gt-masks", "--dense", "--save-repaired", out / "repaired")
    return out, json.loads((out / "run" / "summary.json").read_text()), r.stdout


def read_ply(path):
    data = path.read_bytes()
    header, body = data.split(b"end_header\n", 1)
    header = header.decode()
    assert "format binary_little_endian 1.0" in header
    n = int(re.search(r"element vertex (\d+)", header).group(1))
    props = re.findall(r"property (\w+) (\w+)", header)
    assert props == [("float", "x"), ("float", "y"), ("float", "z"),
                     ("uchar", "red"), ("uchar", "green"), ("uchar", "blue")]
    assert len(body) == 15 * n
    rec = np.frombuffer(body, dtype=np.dtype([("xyz", "<f4", 3), ("rgb", "u1", 3)]), count=n)
    return rec["xyz"], rec["rgb"]


def test_repair_fills_the_people_with_the_static_scene(dense_run):
    _, s, stdout = dense_run
    repair = s["dense"]["repair"]
    assert repair["keyframes"] >= 10
    assert repair["fill_ratio"] >= 0.7
    assert repair["median_depth_error"] <= 0.02  # vs the benchmark's static/depth
    assert repair["compared_pixels"] > 100000
    assert "median depth error" in stdout


def test_dense_map_has_no_ghosts_and_covers_the_seen_scene(dense_run):
    out, s, stdout = dense_run
    m = s["dense"]["map"]
    assert m["ghost_ratio"] <= 0.01
    assert m["completeness"] >= 0.9
    assert m["seen_samples"] > 10000
    xyz, rgb = read_ply(out / "run" / "dense_map.ply")
    assert len(xyz) == s["dense"]["points"] > 50000
    # Every keyframe's cloud is stored (the default 1024 MiB cap is far away), 16 bytes a point.
    st = s["dense"]["storage"]
    assert st["max_memory_mb"] == 1024 and st["evicted_keyframes"] == 0
    assert st["keyframes"] == s["keyframes"] + s["culled_keyframes"]
    assert st["mib"] == pytest.approx(16 * st["points"] / 2**20) and st["points"] >= len(xyz)
    assert np.all(np.isfinite(xyz))
    # Voxel-downsampled at 1 cm: no two points share a voxel.
    keys = np.floor(xyz / 0.01).astype(np.int64)
    assert len(np.unique(keys, axis=0)) >= 0.98 * len(keys)
    picture = cv2.imread(str(out / "run" / "dense_map.png"))
    assert picture is not None and picture.shape == (480, 640, 3)
    assert np.mean(np.any(picture != 40, axis=2)) > 0.1  # the map covers part of the view
    assert "ghosts" in stdout and "completeness" in stdout


def test_eval_map_command_agrees_with_the_run(dense_run, walking):
    out, s, _ = dense_run
    r = lrdslam("eval-map", "--run", out / "run", "--sequence", walking)
    ghosts = float(re.search(r"([\d.]+) % of \d+ points farther", r.stdout).group(1))
    completeness = float(re.search(r"completeness ([\d.]+) %", r.stdout).group(1))
    assert ghosts == pytest.approx(100 * s["dense"]["map"]["ghost_ratio"], abs=0.01)
    assert completeness == pytest.approx(100 * s["dense"]["map"]["completeness"], abs=0.1)


def test_save_repaired_writes_originals_and_repairs(dense_run):
    out, s, _ = dense_run
    repaired = sorted((out / "repaired").glob("*_depth_repaired.png"))
    assert len(repaired) == s["dense"]["repair"]["keyframes"]
    stem = repaired[-1].name[: -len("_depth_repaired.png")]
    for suffix in ("_rgb.png", "_rgb_repaired.png", "_depth.png", "_mask.png"):
        assert (out / "repaired" / (stem + suffix)).exists()
    mask = cv2.imread(str(out / "repaired" / (stem + "_mask.png")), cv2.IMREAD_UNCHANGED)
    before = cv2.imread(str(out / "repaired" / (stem + "_depth.png")), cv2.IMREAD_UNCHANGED)
    after = cv2.imread(str(repaired[-1]), cv2.IMREAD_UNCHANGED)
    assert before.dtype == after.dtype == np.uint16
    assert np.array_equal(before[mask == 0], after[mask == 0])  # only the dynamic region changes
    assert np.mean(before[mask > 0] != after[mask > 0]) > 0.5


def test_dense_map_is_byte_identical_in_deterministic_mode(walking, tmp_path):
    runs = []
    for name in ("a", "b"):
        lrdslam("run", "--sequence", walking, "--out", tmp_path / name, "--quiet", "--deterministic",
                "--mode", "full", "--segmenter", "gt-masks", "--dense", "--max-frames", 60)
        runs.append([(tmp_path / name / f).read_bytes() for f in ("dense_map.ply", "occupancy.bt",
                                                                 "occupancy_2d.pgm", "occupancy_2d.yaml")])
    assert runs[0] == runs[1]


def test_eval_map_names_a_missing_map(walking, tmp_path):
    r = lrdslam("eval-map", "--run", tmp_path, "--sequence", walking, check=False)
    assert r.returncode == 1
    line = r.stderr.strip().splitlines()[-1]
    assert "dense_map.ply" in line and line.startswith("error:")


def test_occupancy_map_and_grid_match_the_scene_without_the_people(dense_run):
    out, s, stdout = dense_run
    o = s["occupancy"]
    assert o["resolution"] == 0.05
    assert o["occupied_voxels"] > 1000 and o["free_voxels"] > 10 * o["occupied_voxels"] / 2
    scene = o["scene"]
    assert scene["precision"] >= 0.95  # the bars in docs/occupancy.md, full mode
    assert scene["recall"] >= 0.90
    assert scene["people_voxels"] > 100  # the people were there to be carved
    assert scene["people_ghost_share"] <= 0.01
    assert scene["path_cells"] > 100
    assert scene["path_blocked_cells"] == 0
    assert scene["grid_precision"] >= 0.95 and scene["grid_recall"] >= 0.90
    # The camera looks level at the start: up is close to the first camera's -y.
    assert o["up"][1] < -0.9
    assert (out / "run" / "occupancy.bt").read_bytes().startswith(b"# Octomap OcTree binary file")
    assert "occupancy vs scene" in stdout and "people's path: 0 of" in stdout


def test_occupancy_grid_is_a_map_server_map(dense_run):
    out, s, _ = dense_run
    meta = yaml.safe_load((out / "run" / "occupancy_2d.yaml").read_text())
    assert meta["image"] == "occupancy_2d.pgm"
    assert meta["resolution"] == pytest.approx(0.05)
    assert len(meta["origin"]) == 3 and meta["negate"] == 0
    assert meta["occupied_thresh"] == 0.65 and meta["free_thresh"] == 0.196
    pgm = cv2.imread(str(out / "run" / meta["image"]), cv2.IMREAD_UNCHANGED)
    assert pgm.dtype == np.uint8
    assert pgm.shape == (s["occupancy"]["grid_height"], s["occupancy"]["grid_width"])
    assert set(np.unique(pgm)) <= {0, 205, 254}
    assert np.count_nonzero(pgm == 0) == s["occupancy"]["grid_occupied_cells"]
    assert np.count_nonzero(pgm == 254) == s["occupancy"]["grid_free_cells"]
    picture = cv2.imread(str(out / "run" / "occupancy_2d.png"))
    assert picture is not None and min(picture.shape[:2]) >= pgm.shape[0] // 2
    blue = (picture[:, :, 0] > 150) & (picture[:, :, 1] < 120) & (picture[:, :, 2] < 60)
    assert np.count_nonzero(blue) > 50  # the trajectory is drawn


def test_occupancy_bt_opens_in_octomaps_own_tools(dense_run, tmp_path):
    # octomap-tools (scripts/install-deps.sh) reads the file as octovis does: every occupied voxel.
    if shutil.which("bt2vrml") is None:
        pytest.skip("octomap-tools is not installed (scripts/install-deps.sh installs it)")
    out, s, _ = dense_run
    shutil.copy(out / "run" / "occupancy.bt", tmp_path / "map.bt")
    r = subprocess.run(["bt2vrml", "map.bt"], cwd=tmp_path, capture_output=True, text=True, check=True)
    written = int(re.search(r"Finished writing (\d+) voxels", r.stdout + r.stderr).group(1))
    assert written == s["occupancy"]["occupied_voxels"]
    assert (tmp_path / "map.bt.wrl").read_text().count("Box { size 0.05 0.05 0.05}") == written


def test_eval_map_judges_the_occupancy_like_the_run(dense_run, walking):
    out, s, _ = dense_run
    r = lrdslam("eval-map", "--run", out / "run", "--sequence", walking)
    m = re.search(r"occupied voxels: precision ([\d.]+) %, recall ([\d.]+) %", r.stdout)
    assert m, r.stdout
    assert float(m.group(1)) == pytest.approx(100 * s["occupancy"]["scene"]["precision"], abs=0.05)
    assert float(m.group(2)) == pytest.approx(100 * s["occupancy"]["scene"]["recall"], abs=0.05)
    assert r.stderr == ""  # OctoMap's own chatter stays out


def test_bad_occupancy_settings_stop_before_tracking(walking, tmp_path):
    config = tmp_path / "bad.yaml"
    config.write_text("occupancy:\n  min_height: 1.5\n  max_height: 0.2\n")
    r = lrdslam("run", "--sequence", walking, "--config", config, "--occupancy", "--quiet",
                "--out", tmp_path / "out", check=False)
    assert r.returncode == 1
    line = r.stderr.strip().splitlines()[-1]
    assert line.startswith("error:") and "bad.yaml:3" in line and "occupancy.max_height" in line
    assert not (tmp_path / "out" / "CameraTrajectory.txt").exists()
