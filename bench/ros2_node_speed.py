#!/usr/bin/python3
"""The ROS 2 node against the CLI: per-frame tracking time of lrdslam_ros2 fed over DDS by
`lrdslam ros2-play` and of `lrdslam run --realtime` on the same frames, both at the camera's pace,
interleaved (CLI, node, CLI, node, ...), each against the Y its own tracking thread measured beside
its frames (`run --yardstick`, the node's yardstick parameter). Bar: the node's median within 10 %
of the CLI's. Also the node's latency from a frame's arrival (colour and depth both received) to
its pose published: median and p99 (node_summary.json latency_ms).

    bench/ros2_node_speed.py [--preset walking_xyz] [--frames 300] [--mode full] [--rounds 2]
                             [--segmenter fnet] [--out out/bench/ros2_node] [--build build/release]

Runs on domain 97 over loopback (ROS_LOCALHOST_ONLY=1).
"""
import argparse
import json
import os
import signal
import statistics
import subprocess
import time

ENV = {**os.environ, "ROS_DOMAIN_ID": "97", "ROS_LOCALHOST_ONLY": "1"}


def totals(track_times):
    with open(track_times) as f:
        rows = [line.split() for line in f if not line.startswith("#")]
    return [float(r[9]) for r in rows if r[10] == "ok"]


def run_cli(build, folder, mode, segmenter, out):
    subprocess.run([f"{build}/bin/lrdslam", "run", "--sequence", folder, "--mode", mode, "--segmenter", segmenter,
                    "--realtime", "--yardstick", "--quiet", "--out", out], check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "summary.json")) as f:
        y = json.load(f)["per_frame"]["yardstick"]["median_ms"]
    return totals(os.path.join(out, "track_times.txt")), y, None


def run_node(build, folder, mode, segmenter, out):
    log = open(out + ".log", "w")
    node = subprocess.Popen([f"{build}/bin/lrdslam_ros2", "--ros-args", "-r", "__node:=lrdslam", "-p",
                             f"mode:={mode}", "-p", f"segmenter:={segmenter}", "-p", "yardstick:=true", "-p",
                             f"output_dir:={out}", "-p", "queue_size:=2"], stdout=log, stderr=subprocess.STDOUT,
                            env=ENV)
    try:
        time.sleep(1.5)
        subprocess.run([f"{build}/bin/lrdslam", "ros2-play", "--sequence", folder, "--rate", "1"], check=True,
                       stdout=subprocess.DEVNULL, env=ENV)
        time.sleep(2)
        node.send_signal(signal.SIGINT)
        if node.wait(120) != 0:
            raise SystemExit(f"the node failed: see {out}.log")
    finally:
        if node.poll() is None:
            node.kill()
    with open(os.path.join(out, "node_summary.json")) as f:
        summary = json.load(f)
    return totals(os.path.join(out, "track_times.txt")), summary["yardstick_ms"], summary


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--preset", default="walking_xyz")
    ap.add_argument("--frames", type=int, default=300)
    ap.add_argument("--mode", default="full")
    ap.add_argument("--segmenter", default="fnet")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--out", default="out/bench/ros2_node")
    ap.add_argument("--build", default="build/release")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    folder = os.path.join(a.out, a.preset)
    if not os.path.exists(os.path.join(folder, "rgb.txt")):
        subprocess.run([f"{a.build}/bin/lrdslam", "synth", "--preset", a.preset, "--frames", str(a.frames),
                        "--out", folder], check=True, stdout=subprocess.DEVNULL)
    print(f"{a.preset}, {a.frames} frames, mode {a.mode}, segmenter {a.segmenter}, both at the camera's pace")
    print(f"{'round':>5} {'run':>5} {'Y ms':>6} {'median ms':>9} {'mean ms':>8} {'median Y':>8} {'mean Y':>7} "
          f"{'tracked':>7} {'latency median/p99 ms':>22}")
    for k in range(a.rounds):
        medians = {}
        for who in ("cli", "node"):
            out = os.path.join(a.out, f"{who}{k}")
            run = run_cli if who == "cli" else run_node
            t, y, summary = run(a.build, folder, a.mode, a.segmenter, out)
            med, mean = statistics.median(t), statistics.fmean(t)
            medians[who] = med / y
            latency = ""
            if summary and summary.get("latency_ms"):
                latency = f"{summary['latency_ms']['median']:.1f} / {summary['latency_ms']['p99']:.1f}"
            print(f"{k:>5} {who:>5} {y:6.2f} {med:9.2f} {mean:8.2f} {med / y:8.2f} {mean / y:7.2f} {len(t):7d} "
                  f"{latency:>22}")
        print(f"round {k}: node / CLI median (in Y) = {medians['node'] / medians['cli']:.3f} (bar: within 10 %)")


if __name__ == "__main__":
    main()
