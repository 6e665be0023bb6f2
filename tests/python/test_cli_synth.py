"""The `lrdslam synth` command-line contract: presets, flags, output layout, errors."""
import json
import os
import subprocess

import cv2
import numpy as np
import pytest

BIN = os.environ.get("LRDSLAM_BIN")
pytestmark = pytest.mark.skipif(not BIN, reason="LRDSLAM_BIN (path of the lrdslam CLI) is not set; run through ctest")


def run(*args):
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=600)


def test_list_names_every_preset():
    out = run("synth", "--list")
    assert out.returncode == 0
    for name in ["walking_static", "walking_xyz", "walking_rpy", "walking_halfsphere", "sitting_static",
                 "sitting_xyz", "sitting_halfsphere", "static_xyz", "static_halfsphere", "static_loop",
                 "walking_loop", "walking_pushed", "walking_long", "walking_circle"]:
        assert name in out.stdout


def test_unknown_preset_is_a_one_line_error(tmp_path):
    out = run("synth", "--preset", "walking_fast", "--out", str(tmp_path / "x"))
    assert out.returncode == 1
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and "walking_fast" in lines[0] and "walking_xyz" in lines[0]


def test_zero_frames_is_an_error(tmp_path):
    out = run("synth", "--preset", "walking_xyz", "--frames", "0", "--out", str(tmp_path / "x"))
    assert out.returncode == 1
    assert "--frames" in out.stderr


def test_writes_tum_layout_with_seed_and_frames(tmp_path):
    seq = tmp_path / "seq"
    out = run("synth", "--preset", "walking_pushed", "--seed", "4", "--frames", "3", "--out", str(seq))
    assert out.returncode == 0, out.stderr
    meta = json.loads((seq / "sequence.json").read_text())
    assert meta["preset"] == "walking_pushed" and meta["seed"] == 4 and meta["frames"] == 3
    assert meta["missing_texture_photos"] == [], "install-deps.sh must provide the photo textures"
    rgb = [l.split() for l in (seq / "rgb.txt").read_text().splitlines() if not l.startswith("#")]
    depth = [l.split() for l in (seq / "depth.txt").read_text().splitlines() if not l.startswith("#")]
    gt = [l.split() for l in (seq / "groundtruth.txt").read_text().splitlines() if not l.startswith("#")]
    assert len(rgb) == len(depth) == len(gt) == 3
    for (t, f), (td, fd) in zip(rgb, depth):
        assert f == f"rgb/{t}.png" and fd == f"depth/{td}.png"
        assert abs(float(t) - float(td)) < 0.02
        img = cv2.imread(str(seq / f), cv2.IMREAD_UNCHANGED)
        d = cv2.imread(str(seq / fd), cv2.IMREAD_UNCHANGED)
        assert img.shape == (480, 640, 3) and img.dtype == np.uint8
        assert d.shape == (480, 640) and d.dtype == np.uint16
        m = cv2.imread(str(seq / "mask" / f"{t}.png"), cv2.IMREAD_UNCHANGED)
        assert set(np.unique(m)) <= {0, 1, 2}
        assert (seq / "static" / f).exists() and (seq / "static" / fd).exists()
    settings = (seq / "settings.yaml").read_text()
    assert settings.startswith("%YAML:1.0") and "Camera.fx: 535.4" in settings and "DepthMapFactor: 5000" in settings


def test_camera_speed_runs_the_camera_path_faster(tmp_path):
    def positions(speed):
        seq = tmp_path / f"speed{speed}"
        args = ["synth", "--preset", "static_loop", "--frames", "40", "--out", str(seq)]
        out = run(*args, *(["--camera-speed", str(speed)] if speed != 1 else []))
        assert out.returncode == 0, out.stderr
        meta = json.loads((seq / "sequence.json").read_text())
        gt = [l.split() for l in (seq / "groundtruth.txt").read_text().splitlines() if not l.startswith("#")]
        return meta, np.array([[float(v) for v in row[1:4]] for row in gt])

    meta1, p1 = positions(1)
    meta2, p2 = positions(2)
    assert "camera_speed" not in meta1 and meta2["camera_speed"] == 2.0
    path1 = np.linalg.norm(np.diff(p1, axis=0), axis=1).sum()
    path2 = np.linalg.norm(np.diff(p2, axis=0), axis=1).sum()
    assert 1.8 < path2 / path1 < 2.2  # twice the distance in the same frames
    assert run("synth", "--preset", "static_loop", "--camera-speed", "0", "--out", str(tmp_path / "x")).returncode != 0


def test_export_voc_layout_labels_and_split(tmp_path):
    voc = tmp_path / "voc"
    out = run("synth", "--export-voc", str(voc), "--images", "30")
    assert out.returncode == 0, out.stderr
    train = (voc / "ImageSets/Segmentation/train.txt").read_text().split()
    val = (voc / "ImageSets/Segmentation/val.txt").read_text().split()
    assert len(train) == 25 and len(val) == 5, "whole sequences go to validation"
    assert not set(train) & set(val)
    seeds = {int(n.split("_")[-2]) for n in train + val}
    assert min(seeds) >= 1000, "training seeds are disjoint from evaluation seeds"
    voc_ids = {0, 9, 11, 15, 16, 18, 20}
    person = 0
    for name in train + val:
        img = cv2.imread(str(voc / "JPEGImages" / f"{name}.jpg"))
        lab = cv2.imread(str(voc / "SegmentationClassAug" / f"{name}.png"), cv2.IMREAD_UNCHANGED)
        assert img.shape == (480, 640, 3) and lab.shape == (480, 640) and lab.dtype == np.uint8
        assert set(np.unique(lab)) <= voc_ids
        person += int((lab == 15).sum())
    assert person > 0


def test_export_voc_refuses_evaluation_seeds(tmp_path):
    out = run("synth", "--export-voc", str(tmp_path / "v"), "--images", "2", "--seed", "1")
    assert out.returncode == 1 and "reserved for evaluation" in out.stderr


def test_realism_tum_records_its_effects_and_the_users_calibration(tmp_path):
    seq = tmp_path / "seq"
    out = run("synth", "--preset", "walking_xyz", "--frames", "3", "--realism", "tum",
              "--realism-off", "rolling_shutter,motion_blur", "--out", str(seq))
    assert out.returncode == 0, out.stderr
    meta = json.loads((seq / "sequence.json").read_text())
    realism = meta["realism"]
    assert realism["profile"] == "tum"
    assert realism["effects"]["rolling_shutter"] is False and realism["effects"]["motion_blur"] is False
    assert all(on for name, on in realism["effects"].items() if name not in ("rolling_shutter", "motion_blur"))
    assert realism["rolling_shutter"]["readout_s"] == pytest.approx(0.028)
    # settings.yaml: the lens distortion, and focal lengths 0.6 % / -0.4 % off the rendering camera.
    settings = (seq / "settings.yaml").read_text()
    values = dict(l.split(": ") for l in settings.splitlines() if l.startswith("Camera.") and ": " in l)
    assert float(values["Camera.k1"]) == pytest.approx(0.2312 - 0.02)
    assert float(values["Camera.fx"]) == pytest.approx(535.4 * 1.006)
    assert "Camera.readoutTime" not in values  # the rolling shutter is off: a global shutter
    # Ground truth at the motion-capture rate, covering the images.
    gt = [float(l.split()[0]) for l in (seq / "groundtruth.txt").read_text().splitlines() if not l.startswith("#")]
    rgb = [float(l.split()[0]) for l in (seq / "rgb.txt").read_text().splitlines() if not l.startswith("#")]
    assert np.allclose(np.diff(gt), 0.01, rtol=0, atol=2e-6) and gt[0] < rgb[0] and gt[-1] > rgb[-1]
    # Depth in the driver's whole millimetres.
    d = cv2.imread(str(seq / "depth" / f"{sorted(os.listdir(seq / 'depth'))[0]}"), cv2.IMREAD_UNCHANGED)
    assert d.max() > 0 and np.all(d % 5 == 0)
    # The clean profile writes no realism record and a distortion-free calibration.
    clean = tmp_path / "clean"
    assert run("synth", "--preset", "walking_xyz", "--frames", "1", "--out", str(clean)).returncode == 0
    assert "realism" not in json.loads((clean / "sequence.json").read_text())
    assert "Camera.k1: 0\n" in (clean / "settings.yaml").read_text()
    assert "readoutTime" not in (clean / "settings.yaml").read_text()
    # With the rolling shutter on, the calibration carries its readout time (tracking compensates it).
    rolling = tmp_path / "rolling"
    assert run("synth", "--preset", "walking_xyz", "--frames", "1", "--realism", "tum",
               "--out", str(rolling)).returncode == 0
    assert "Camera.readoutTime: 0.028\n" in (rolling / "settings.yaml").read_text()


def test_realism_tum_moves_the_camera_as_fast_as_tums_sequence():
    # The whole preset's motion (no frame rendered), as TUM's statistics script computes it, within
    # 15 % (the target of docs/synthetic-benchmark.md, "Camera motion against TUM's") of the figures
    # TUM publishes for fr3/walking_rpy (0.091 m/s, 20.90 deg/s).
    def speeds(*extra):
        out = run("synth", "--preset", "walking_rpy", "--motion-stats", *extra)
        assert out.returncode == 0, out.stderr
        ours, tums = [l.split("mean ")[1].split() for l in out.stdout.splitlines() if "mean " in l]
        return (float(ours[0]), float(ours[3])), (float(tums[0]), float(tums[3]))
    (speed, turn), (tum_speed, tum_turn) = speeds("--realism", "tum")
    assert (tum_speed, tum_turn) == (0.091, 20.90)
    assert speed == pytest.approx(tum_speed, rel=0.15) and turn == pytest.approx(tum_turn, rel=0.15)
    # The clean profile keeps the smooth path (a camera that barely translates), and so does an
    # ablation of the effect.
    for extra in ((), ("--realism", "tum", "--realism-off", "camera_motion")):
        (speed, _), _ = speeds(*extra)
        assert speed < 0.2 * tum_speed


def test_realism_errors_are_one_line(tmp_path):
    out = run("synth", "--preset", "walking_xyz", "--frames", "1", "--realism", "tum", "--realism-off", "blurr",
              "--out", str(tmp_path / "x"))
    assert out.returncode == 1
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and "blurr" in lines[0] and "rolling_shutter" in lines[0]
    out = run("synth", "--preset", "walking_xyz", "--realism", "kinect2", "--out", str(tmp_path / "y"))
    assert out.returncode != 0 and "kinect2" in out.stderr
