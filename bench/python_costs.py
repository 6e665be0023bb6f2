#!/usr/bin/python3
"""What each call of the Python module costs (docs/python.md): medians over repeated calls on a
walking_xyz sequence, after tracking it with the dense map and occupancy on. Milliseconds and, for
the per-frame calls, multiples of Y (bench_orb on the same frames, run right after).

    PYTHONPATH=build/release/python bench/python_costs.py [--frames 300] [--out out/bench/python]
"""
import argparse
import os
import re
import statistics
import subprocess
import time

import numpy as np

import lrdslam


def median_ms(fn, repeats):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append((time.perf_counter() - t0) * 1000.0)
    return statistics.median(times)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=300)
    ap.add_argument("--out", default="out/bench/python")
    ap.add_argument("--build", default="build/release")
    a = ap.parse_args()
    folder = os.path.join(a.out, "walking_xyz")
    if not os.path.exists(os.path.join(folder, "rgb.txt")):
        subprocess.run([f"{a.build}/bin/lrdslam", "synth", "--preset", "walking_xyz", "--frames", str(a.frames),
                        "--out", folder], check=True, stdout=subprocess.DEVNULL)
    seq = lrdslam.io.read_sequence(folder)
    rendered = lrdslam.synth.render("walking_xyz", frames=a.frames)
    rows = [("io.read_sequence(folder)", median_ms(lambda: lrdslam.io.read_sequence(folder), 5)),
            ("seq[i] (PNG decode, BGR->RGB)", median_ms(lambda: seq[len(seq) // 2], 30)),
            ("synth.render(...)[i] (render one frame)", median_ms(lambda: rendered[len(rendered) // 2], 10))]
    frames = [seq[i] for i in range(len(seq))]
    slam = lrdslam.System(sequence=folder, mode="full", dense=True, occupancy=True)
    call, inside = [], []
    for f in frames:
        t0 = time.perf_counter()
        r = slam.track_rgbd(f.rgb, f.depth, f.timestamp)
        call.append((time.perf_counter() - t0) * 1000.0)
        inside.append(r.timing["total"] * 1000.0)
    slam.shutdown()
    overhead = statistics.median(np.subtract(call, inside))
    rows += [("System.track_rgbd (full mode, dense on)", statistics.median(call)),
             ("  of which outside the library (wrap, GIL, result)", overhead),
             ("System.trajectory()", median_ms(slam.trajectory, 10)),
             ("System.map_snapshot()", median_ms(slam.map_snapshot, 10)),
             ("System.dense_map()", median_ms(slam.dense_map, 3)),
             ("System.occupancy()", median_ms(slam.occupancy, 3))]
    stats = slam.map_stats()
    r = subprocess.run([f"{a.build}/bin/bench_orb", folder, str(a.frames)], capture_output=True, text=True, check=True)
    y = float(re.search(r"^Y .* median\s+([\d.]+) ms", r.stdout, re.M).group(1))
    print(f"walking_xyz, {a.frames} frames; map: {stats['keyframes']} keyframes, {stats['map_points']} points, "
          f"dense map {len(slam.dense_map().points)} points; Y = {y:.2f} ms")
    print("| call | median (ms) | median (Y) |")
    print("|---|---|---|")
    for name, ms in rows:
        print(f"| {name} | {ms:.3f} | {ms / y:.3f} |")


if __name__ == "__main__":
    main()
