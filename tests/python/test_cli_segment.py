"""`lrdslam segment --model PRESET IMAGE... --out DIR` (segmentation presets): masks, overlays and
label maps that agree with ground truth (our FNet on synthetic frames) and with the reference masks
of a real model (ESPNetv2 from ../shared); the default segmenter a semantic run picks; one-line
errors."""
import json
import os
from pathlib import Path

import cv2
import numpy as np
import pytest

from cli import lrdslam, synth_input

ROOT = Path(__file__).resolve().parents[2]
SHARED = Path(os.environ.get("LRD_SHARED_DIR") or ROOT.parent / "shared")
ESPNET = SHARED / "models/espnetv2_voc/espnetv2_s2.0_voc_384x288.onnx"


@pytest.fixture(scope="module")
def walking(tmp_path_factory):
    d = tmp_path_factory.mktemp("seq") / "walking_xyz"
    synth_input("--preset", "walking_xyz", "--frames", 40, "--out", d)
    return d


def iou(a, b):
    union = np.count_nonzero(a | b)
    return 1.0 if union == 0 else np.count_nonzero(a & b) / union


def test_fnet_masks_match_the_synthetic_ground_truth(walking, tmp_path):
    names = sorted((walking / "rgb").iterdir())[::10]
    r = lrdslam("segment", "--model", "fnet", "--out", tmp_path, *names)
    assert "fnet-lite.onnx" in r.stdout
    scores = []
    for rgb in names:
        mask = cv2.imread(str(tmp_path / f"{rgb.stem}_mask.png"), cv2.IMREAD_UNCHANGED)
        labels = cv2.imread(str(tmp_path / f"{rgb.stem}_labels.png"), cv2.IMREAD_UNCHANGED)
        overlay = cv2.imread(str(tmp_path / f"{rgb.stem}_overlay.png"), cv2.IMREAD_COLOR)
        gt = cv2.imread(str(walking / "mask" / rgb.name), cv2.IMREAD_UNCHANGED)
        assert mask.shape == gt.shape == labels.shape == overlay.shape[:2]
        assert set(np.unique(mask)) <= {0, 255}
        assert np.array_equal(mask == 255, labels == 15)  # the only VOC class our renders have people of
        if np.count_nonzero(gt == 1) > 2000:
            scores.append(iou(mask == 255, gt == 1))
    assert scores, "no frame with a person in view"
    assert np.median(scores) > 0.6, scores  # held-out person IoU of the shipped model: 0.82


@pytest.mark.skipif(not ESPNET.exists(), reason=f"no ESPNetv2 model at {ESPNET} (shared folder absent)")
def test_espnet_preset_reproduces_the_reference_labels(tmp_path):
    photo = SHARED / "data/people/mrcnn_ex02.jpg"
    lrdslam("segment", "--model", "espnetv2-voc", "--model-file", ESPNET, "--out", tmp_path, photo)
    labels = cv2.imread(str(tmp_path / "mrcnn_ex02_labels.png"), cv2.IMREAD_UNCHANGED)
    ref = cv2.imread(str(SHARED / "data/people/ref_masks/espnetv2_s2.0_voc_384x288/mrcnn_ex02.png"),
                     cv2.IMREAD_UNCHANGED)
    assert np.mean(labels == ref) >= 0.98
    mask = cv2.imread(str(tmp_path / "mrcnn_ex02_mask.png"), cv2.IMREAD_UNCHANGED)
    # Person and horse are dynamic; the car is not.
    assert np.array_equal(mask == 255, np.isin(labels, [3, 8, 10, 12, 13, 15, 17]))
    assert np.count_nonzero(labels == 7) > 1000 and not np.any(mask[labels == 7])


def test_semantic_run_without_a_segmenter_uses_fnet_on_synthetic_data(walking, tmp_path):
    lrdslam("run", "--sequence", walking, "--out", tmp_path, "--quiet", "--deterministic",
            "--mode", "semantic", "--max-frames", 10)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert "fnet-lite.onnx" in summary["segmentation"]


@pytest.mark.parametrize("args, words", [
    (["--model", "espnetv2-voc"], ["espnetv2-voc", "model file"]),
    (["--model", "selfy"], ["selfy", "selfie-landscape"]),
    (["--model", "fnet", "--model-file", "/nonexistent/net.onnx"], ["/nonexistent/net.onnx", "not found"]),
])
def test_bad_model_choice_is_one_line_error(tmp_path, args, words):
    img = tmp_path / "a.png"
    cv2.imwrite(str(img), np.zeros((48, 64, 3), np.uint8))
    r = lrdslam("segment", *args, "--out", tmp_path / "o", img, check=False)
    assert r.returncode == 1
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:"), r.stderr
    for w in words:
        assert w in lines[0]


def test_unreadable_image_is_named(tmp_path):
    bad = tmp_path / "broken.png"
    bad.write_bytes(b"not a png")
    for img in (bad, tmp_path / "missing.jpg"):
        r = lrdslam("segment", "--model", "fnet", "--out", tmp_path / "o", img, check=False)
        assert r.returncode == 1
        assert str(img) in r.stderr.strip().splitlines()[-1]
