#!/usr/bin/python3
"""Track a TUM-layout sequence folder (TUM RGB-D, Bonn RGB-D Dynamic, `lrdslam synth` output) or a
bag with lrd-slam from Python, and write OUT/CameraTrajectory.txt as `lrdslam run` does.

    PYTHONPATH=build/release/python examples/python/track_folder.py SEQ OUT --mode full [--plot]

The camera is found as `lrdslam run` finds it (settings.yaml, the TUM folder name, ...), so with
--deterministic the trajectory is byte-identical to `lrdslam run --sequence SEQ --deterministic`.
"""
import argparse
import pathlib
import sys
import time

import lrdslam


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("sequence", type=pathlib.Path)
    p.add_argument("out", type=pathlib.Path)
    p.add_argument("--mode", choices=["static", "semantic", "geometric", "full"])
    p.add_argument("--segmenter")
    p.add_argument("--deterministic", action="store_true")
    p.add_argument("--plot", action="store_true", help="OUT/trajectory.png: estimate against ground truth")
    args = p.parse_args()

    seq = lrdslam.io.read_sequence(args.sequence)
    slam = lrdslam.System(sequence=seq, mode=args.mode, segmenter=args.segmenter, deterministic=args.deterministic)
    print(f"{seq}: camera from {slam.camera_source}; mode {slam.mode}; segmentation {slam.segmentation}")
    start, lost = time.perf_counter(), 0
    for f in seq:
        r = slam.track_rgbd(f.rgb, f.depth, f.timestamp)
        lost += r.state == "lost"
    slam.shutdown()
    args.out.mkdir(parents=True, exist_ok=True)
    slam.save_trajectory(args.out / "CameraTrajectory.txt")
    wall = time.perf_counter() - start
    print(f"{len(seq)} frames in {wall:.1f} s ({len(seq) / wall:.1f} frames/s), {lost} lost; "
          f"wrote {args.out / 'CameraTrajectory.txt'}")
    if seq.ground_truth is not None:
        ate = lrdslam.eval.ate(seq.ground_truth, slam.trajectory())
        print(f"ATE RMSE {ate.rmse * 100:.2f} cm over {ate.pairs} poses")
        if args.plot:
            plot(seq.ground_truth, slam.trajectory(), ate.alignment, args.out / "trajectory.png")


def plot(gt, est, alignment, file):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit("--plot needs matplotlib (Debian: apt-get install python3-matplotlib)")
    aligned = est[:, 1:4] @ alignment[:3, :3].T + alignment[:3, 3]
    fig, ax = plt.subplots(figsize=(6, 5))
    ax.plot(gt[:, 1], gt[:, 2], label="ground truth", color="black", lw=1)
    ax.plot(aligned[:, 0], aligned[:, 1], label="lrd-slam (aligned)", color="tab:red", lw=1)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.axis("equal")
    ax.legend()
    fig.tight_layout()
    fig.savefig(file, dpi=120)
    print(f"wrote {file}")


if __name__ == "__main__":
    try:
        main()
    except lrdslam.Error as e:
        sys.exit(f"track_folder: {e}")
