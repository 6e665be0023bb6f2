"""FNet CPU speed in OpenCV DNN, relative to ORB extraction on the same machine.

  /usr/bin/python3 training/bench_fnet.py [--threads 2] [--size 320x240] [--lite-size 160x120] [--runs 30]

Y = median wall time of cv2.ORB_create(1000, 1.2, 8).detectAndCompute on a 640x480 grey photo
(the per-frame cost the SLAM front end already pays). fnet-lite's target is <= 0.4 Y per frame on
2 cores, i.e. segmentation costs less than half a feature extraction; it runs at 160x120 (the
shipped model's input, the whole camera frame resized), full FNet at 320x240. Weights are random
(speed does not depend on them); the models are exported with training/fnet/export.py, exactly as
the C++ side will load them.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
import warnings

import cv2
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

PHOTO = "/usr/share/doc/opencv-doc/examples/data/baboon.jpg"  # textured; package opencv-doc


def grey_640x480() -> np.ndarray:
    img = cv2.imread(PHOTO, cv2.IMREAD_GRAYSCALE)
    if img is None:  # fallback: deterministic texture
        rng = np.random.default_rng(0)
        img = cv2.GaussianBlur(rng.integers(0, 256, (480, 640), dtype=np.uint8), (0, 0), 2.0)
    return cv2.resize(img, (640, 480), interpolation=cv2.INTER_AREA)


def dnn_runner(onnx_path: str, size):
    net = cv2.dnn.readNetFromONNX(onnx_path)
    net.setPreferableBackend(cv2.dnn.DNN_BACKEND_OPENCV)
    net.setPreferableTarget(cv2.dnn.DNN_TARGET_CPU)
    bgr = cv2.imread(PHOTO) if os.path.exists(PHOTO) else np.zeros((480, 640, 3), np.uint8)
    blob = cv2.dnn.blobFromImage(cv2.resize(bgr, size), 1 / 255.0, size, swapRB=True, crop=False)

    def run():
        net.setInput(blob)
        net.forward()
    return run


def interleaved_ms(fns, runs: int, warmup: int = 3):
    """Median ms of each fn, timed round-robin so that load from other processes (a parallel build)
    hits all of them alike and the ratios stay meaningful."""
    for f in fns:
        for _ in range(warmup):
            f()
    times = [[] for _ in fns]
    for _ in range(runs):
        for f, ts in zip(fns, times):
            t0 = time.perf_counter()
            f()
            ts.append((time.perf_counter() - t0) * 1e3)
    return [statistics.median(ts) for ts in times]


def main(argv=None) -> int:
    import torch
    from training.fnet.export import export_onnx, parse_size
    from training.fnet.model import build_model

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--size", type=parse_size, default=(320, 240), help="fnet's input WxH (default 320x240)")
    ap.add_argument("--lite-size", type=parse_size, default=(160, 120),
                    help="fnet-lite's input WxH (default 160x120, the shipped model's)")
    ap.add_argument("--runs", type=int, default=30, help="timed runs for ORB and fnet-lite (fnet: runs/3)")
    a = ap.parse_args(argv)
    cv2.setNumThreads(a.threads)
    torch.set_num_threads(1)
    warnings.filterwarnings("ignore")

    orb, grey = cv2.ORB_create(1000, 1.2, 8), grey_640x480()
    noise = np.random.default_rng(0).integers(0, 256, (480, 640), dtype=np.uint8)
    with tempfile.TemporaryDirectory() as tmp:
        runners, rows = [], []
        for name, size in (("fnet-lite", a.lite_size), ("fnet", a.size)):
            path = os.path.join(tmp, name + ".onnx")
            model = build_model(name)
            export_onnx(model, path, size, verify=False)
            runners.append(dnn_runner(path, size))
            rows.append([name, sum(p.numel() for p in model.parameters())])
        y, y_noise, lite = interleaved_ms([lambda: orb.detectAndCompute(grey, None),
                                           lambda: orb.detectAndCompute(noise, None), runners[0]], a.runs)
        (y2, full), = [interleaved_ms([lambda: orb.detectAndCompute(grey, None), runners[1]],
                                      max(5, a.runs // 3))]
    print(f"OpenCV {cv2.__version__}, {a.threads} thread(s), input fnet-lite {a.lite_size[0]}x{a.lite_size[1]}, "
          f"fnet {a.size[0]}x{a.size[1]}")
    print(f"Y (ORB 1000/1.2/8 detectAndCompute, 640x480 grey photo {os.path.basename(PHOTO)}): {y:.2f} ms"
          f"  [uniform-noise image: {y_noise:.2f} ms]")
    rows[0] += [lite, lite / y, lite / y_noise]
    rows[1] += [full, full / y2, full / y2 * y / y_noise]
    print("| model | params | ms/frame | ratio to Y (photo) | ratio to Y (noise) |")
    print("|---|---:|---:|---:|---:|")
    for name, n, ms, r, rn in rows:
        print(f"| {name} | {n / 1e6:.2f} M | {ms:.2f} | {r:.3f} | {rn:.3f} |")
    r = rows[0][3]
    print(f"fnet-lite target <= 0.4 Y (photo): {'MET' if r <= 0.4 else 'NOT MET'} ({r:.3f} Y)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
