#!/usr/bin/python3
"""The Python module against the CLI: per-frame time of lrd-slam driven from Python
(lrdslam.System.track_rgbd, timed around the call: the numpy wrapping, the GIL release and the
result's conversion included) and of `lrdslam run --preload` (track_times.txt's total: the
tracking thread's time per frame) on the same frames, interleaved (CLI, Python, CLI, Python, ...),
each against the Y measured in that run (OpenCV's ORB timed on every frame in the tracking thread
beside the extraction: `run --yardstick`, `System(yardstick=True)`; not part of the per-frame time,
and taken out of the Python call's wall time). Both decode every frame before the first is tracked,
so neither competes with a decoding thread. Bar: Python's median within 5 % of the CLI's, in Y.

    PYTHONPATH=build/release/python bench/python_speed.py [--preset walking_xyz] [--frames 300]
        [--mode full] [--rounds 3] [--out out/bench/python] [--build build/release]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time


def run_cli(build, folder, mode, out):
    subprocess.run([f"{build}/bin/lrdslam", "run", "--sequence", folder, "--mode", mode, "--preload", "--quiet",
                    "--yardstick", "--out", out], check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "track_times.txt")) as f:
        rows = [line.split() for line in f if not line.startswith("#")]
    with open(os.path.join(out, "summary.json")) as f:
        y = json.load(f)["per_frame"]["yardstick"]["median_ms"]
    return [float(r[9]) for r in rows if r[10] == "ok"], y


def run_python(folder, mode):
    import lrdslam
    seq = lrdslam.io.read_sequence(folder)
    frames = [seq[i] for i in range(len(seq))]  # decoded before tracking, as --preload does
    slam = lrdslam.System(sequence=folder, mode=mode, yardstick=True)
    wall, inner, ys = [], [], []
    for f in frames:
        t0 = time.perf_counter()
        r = slam.track_rgbd(f.rgb, f.depth, f.timestamp)
        dt = time.perf_counter() - t0 - r.timing["yardstick"]
        ys.append(r.timing["yardstick"] * 1000.0)
        if r.state == "ok":
            wall.append(dt * 1000.0)
            inner.append(r.timing["total"] * 1000.0)
    slam.shutdown()
    return wall, inner, statistics.median(ys)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--preset", default="walking_xyz")
    ap.add_argument("--frames", type=int, default=300)
    ap.add_argument("--mode", default="full")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--out", default="out/bench/python")
    ap.add_argument("--build", default="build/release")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    folder = os.path.join(a.out, a.preset)
    if not os.path.exists(os.path.join(folder, "rgb.txt")):
        subprocess.run([f"{a.build}/bin/lrdslam", "synth", "--preset", a.preset, "--frames", str(a.frames),
                        "--out", folder], check=True, stdout=subprocess.DEVNULL)
    print(f"{a.preset}, {a.frames} frames, mode {a.mode}; per-frame ms over tracked frames; Y = the run's own")
    print("| round | run | Y (ms) | median (ms) | mean (ms) | median (Y) | mean (Y) | frames |")
    print("|---|---|---|---|---|---|---|---|")
    ratios = []
    for k in range(a.rounds):
        cli, y_cli = run_cli(a.build, folder, a.mode, os.path.join(a.out, f"cli_{k}"))
        wall, inner, y_py = run_python(folder, a.mode)
        rows = [("CLI", y_cli, cli), ("Python (call)", y_py, wall), ("Python (inside)", y_py, inner)]
        for name, y, v in rows:
            med, mean = statistics.median(v), statistics.fmean(v)
            print(f"| {k} | {name} | {y:.2f} | {med:.2f} | {mean:.2f} | {med / y:.2f} | {mean / y:.2f} | {len(v)} |")
        ratios.append((statistics.median(wall) / y_py) / (statistics.median(cli) / y_cli))
        sys.stdout.flush()
    print("Python (call) median over the CLI's, in Y: " + ", ".join(f"{r:.3f}" for r in ratios))


if __name__ == "__main__":
    main()
