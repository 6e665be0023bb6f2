#!/usr/bin/python3
"""What autosaving costs tracking: `lrdslam run --realtime` (frames at the camera's pace, as a
robot gets them) without and with `--autosave`, interleaved (without, with, without, with, ...),
each against the Y its own tracking thread measured beside its frames (`run --yardstick`). The
figure: the median per-frame tracking time (FrameTiming total) of the frames tracked while a save
was under way (summary.json autosave.frame_indices_during_saves) against the median of the same
frames in the run without autosave, both in Y. Bar: within 10 %. Also every frame's median with
and without, the map mutex held per save, the save's duration and the map file's size.

    bench/autosave_speed.py [--preset walking_xyz] [--frames 900] [--period 0.5] [--mode full]
                            [--rounds 3] [--out out/bench/autosave] [--build build/release]
"""
import argparse
import json
import os
import statistics
import subprocess


def totals(track_times):
    """Frame index -> total ms of the frames tracked."""
    with open(track_times) as f:
        rows = [line.split() for line in f if not line.startswith("#")]
    return {int(r[0]): float(r[9]) for r in rows if r[10] == "ok"}


def run(args, out, period):
    os.makedirs(out, exist_ok=True)
    cmd = [f"{args.build}/bin/lrdslam", "run", "--synth", args.preset, "--frames", str(args.frames), "--mode",
           args.mode, "--realtime", "--yardstick", "--quiet", "--out", out, "--save-map",
           os.path.join(out, "map.lrdmap")]
    if period > 0:
        cmd += ["--autosave", str(period)]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    return summary, totals(os.path.join(out, "track_times.txt"))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--preset", default="walking_xyz")
    ap.add_argument("--frames", type=int, default=900)
    ap.add_argument("--period", type=float, default=0.5)
    ap.add_argument("--mode", default="full")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--out", default="out/bench/autosave")
    ap.add_argument("--build", default="build/release")
    args = ap.parse_args()
    print("| round | Y without / with | frames during saves | those frames without | with | ratio | "
          "all frames without | with | saves | lock median / max | save median | map file |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    ratios = []
    for r in range(args.rounds):
        base, base_totals = run(args, os.path.join(args.out, f"without_{r}"), 0)
        with_, with_totals = run(args, os.path.join(args.out, f"with_{r}"), args.period)
        y0 = base["per_frame"]["yardstick"]["median_ms"]
        y1 = with_["per_frame"]["yardstick"]["median_ms"]
        a = with_["autosave"]
        frames = [i for i in a["frame_indices_during_saves"] if i in base_totals and i in with_totals]
        during_without = statistics.median(base_totals[i] for i in frames) / y0
        during_with = statistics.median(with_totals[i] for i in frames) / y1
        ratios.append(during_with / during_without)
        all_without = statistics.median(base_totals.values()) / y0
        all_with = statistics.median(with_totals.values()) / y1
        size = os.path.getsize(os.path.join(args.out, f"with_{r}", "map.lrdmap"))
        print(f"| {r + 1} | {y0:.2f} / {y1:.2f} ms | {len(frames)} | {during_without:.2f} Y | {during_with:.2f} Y | "
              f"{during_with / during_without:.3f} | {all_without:.2f} Y | {all_with:.2f} Y | {a['saves']} | "
              f"{a['lock_median_ms']:.2f} / {a['lock_max_ms']:.2f} ms | {a['save_median_ms']:.1f} ms | "
              f"{size / 1e6:.2f} MB |", flush=True)
    print(f"\nframes during saves, with / without: median {statistics.median(ratios):.3f} over {len(ratios)} "
          f"rounds (bar: 1.10)")


if __name__ == "__main__":
    main()
