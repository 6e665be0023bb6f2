#!/usr/bin/python3
"""The node against the CLI (bench/results/ros_node.md): per-frame tracking time of lrdslam_ros fed by
`rosbag play` and of `lrdslam run --bag --realtime` on the same bag, both at the camera's pace,
interleaved (CLI, node, CLI, node, ...), each reported against Y measured between them (bench_orb
on the same frames). Bar: the node's median within 10 % of the CLI's.

    bench/ros_node_speed.py [--preset walking_xyz] [--frames 300] [--mode full] [--rounds 2]
                            [--out out/bench/ros_node] [--build build/release]

Prints per run the median and mean total_ms of track_times.txt (tracking thread, without decoding
or message conversion), the frames tracked, and the ratios to Y; then the node's median over the
CLI's per round.
"""
import argparse
import os
import re
import signal
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests", "ros", "python"))


def totals(track_times):
    with open(track_times) as f:
        rows = [line.split() for line in f if not line.startswith("#")]
    return [float(r[9]) for r in rows if r[10] == "ok"]


def yardstick(build, folder, frames):
    r = subprocess.run([f"{build}/bin/bench_orb", folder, str(frames)], capture_output=True, text=True, check=True)
    return float(re.search(r"^Y .* median\s+([\d.]+) ms", r.stdout, re.M).group(1))


def run_cli(build, bag, mode, segmenter, out):
    subprocess.run([f"{build}/bin/lrdslam", "run", "--bag", bag, "--mode", mode, "--segmenter", segmenter,
                    "--realtime", "--quiet", "--out", out], check=True, stdout=subprocess.DEVNULL)
    return totals(os.path.join(out, "track_times.txt"))


def run_node(master, build, bag, mode, segmenter, out):
    from rosenv import Node, play

    node = Node(master, out + ".log", binary=f"{build}/bin/lrdslam_ros", mode=mode, segmenter=segmenter,
                output_dir=out, queue_size=2)
    try:
        node.wait_ready()
        time.sleep(1)
        play(master, bag, 1.0, delay=2.0)
        time.sleep(2)
        if node.interrupt() != 0:
            raise SystemExit(f"the node failed:\n{node.output()}")
    finally:
        node.kill()
    return totals(os.path.join(out, "track_times.txt"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--preset", default="walking_xyz")
    ap.add_argument("--frames", type=int, default=300)
    ap.add_argument("--mode", default="full")
    ap.add_argument("--segmenter", default="fnet")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--out", default="out/bench/ros_node")
    ap.add_argument("--build", default="build/release")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    folder, bag = os.path.join(a.out, a.preset), os.path.join(a.out, a.preset + ".bag")
    if not os.path.exists(bag):
        subprocess.run([f"{a.build}/bin/lrdslam", "synth", "--preset", a.preset, "--frames", str(a.frames),
                        "--out", folder, "--bag", bag], check=True, stdout=subprocess.DEVNULL)

    from pathlib import Path

    from rosenv import RosMaster

    master = RosMaster(Path(os.path.abspath(a.out)) / "roshome").start()
    import rospy

    rospy.init_node("lrdslam_bench", anonymous=True, disable_signals=True)
    print(f"{a.preset}, {a.frames} frames, mode {a.mode}, segmenter {a.segmenter}, both at the camera's pace")
    print(f"{'round':>5} {'run':>5} {'Y ms':>6} {'median ms':>9} {'mean ms':>8} {'median Y':>8} {'mean Y':>7} {'tracked':>7}")
    try:
        for k in range(a.rounds):
            medians = {}
            for who in ("cli", "node"):
                out = os.path.join(a.out, f"{who}{k}")
                t = (run_cli(a.build, bag, a.mode, a.segmenter, out) if who == "cli"
                     else run_node(master, a.build, bag, a.mode, a.segmenter, out))
                y = yardstick(a.build, folder, 50)
                med, mean = statistics.median(t), statistics.fmean(t)
                medians[who] = med / y
                print(f"{k:>5} {who:>5} {y:6.2f} {med:9.2f} {mean:8.2f} {med / y:8.2f} {mean / y:7.2f} {len(t):7d}")
            print(f"round {k}: node / CLI median (in Y) = {medians['node'] / medians['cli']:.3f} (bar: within 10 %)")
    finally:
        rospy.signal_shutdown("done")
        master.stop()


if __name__ == "__main__":
    main()
