#!/usr/bin/python3
"""The paper's comparison on a synthetic preset, from Python: each dynamic mode on the same
rendered frames, ATE and RPE as the paper's Tables 4-7 print them, and the improvement rate eta
over `static` (ORB-SLAM2).

    PYTHONPATH=build/release/python examples/python/modes_table.py --preset walking_xyz --frames 300
"""
import argparse
import sys

import lrdslam

MODES = ["static", "semantic", "geometric", "full"]


def run(seq, mode, deterministic):
    slam = lrdslam.System(sequence=seq, mode=mode, deterministic=deterministic)
    for f in seq:
        slam.track_rgbd(f.rgb, f.depth, f.timestamp)
    slam.shutdown()
    est = slam.trajectory()
    return lrdslam.eval.ate(seq.ground_truth, est), lrdslam.eval.rpe(seq.ground_truth, est)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--preset", default="walking_xyz", choices=lrdslam.synth.presets())
    p.add_argument("--frames", type=int, default=300)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--realism", default="clean", choices=["clean", "tum"])
    p.add_argument("--modes", default=",".join(MODES))
    p.add_argument("--deterministic", action="store_true")
    args = p.parse_args()
    seq = lrdslam.synth.render(args.preset, seed=args.seed, frames=args.frames, realism=args.realism)
    rows = {mode: run(seq, mode, args.deterministic) for mode in args.modes.split(",")}
    print(f"{args.preset}, {len(seq)} frames, realism {args.realism}")
    print(f"{'mode':<10}{'ATE rmse':>10}{'mean':>9}{'median':>9}{'std':>9}{'RPE t rmse':>12}{'RPE r rmse':>12}"
          f"{'eta ATE':>9}")
    base = rows.get("static")
    for mode, (ate, rpe) in rows.items():
        eta = f"{lrdslam.eval.improvement(base[0].rmse, ate.rmse):+.1f}%" if base and mode != "static" else ""
        print(f"{mode:<10}{ate.rmse:>10.4f}{ate.mean:>9.4f}{ate.median:>9.4f}{ate.std:>9.4f}"
              f"{rpe.trans.rmse:>12.4f}{rpe.rot.rmse:>12.3f}{eta:>9}")
    print("ATE in m; RPE in m/s and deg/s; eta = (static - mode) / static.")


if __name__ == "__main__":
    try:
        main()
    except lrdslam.Error as e:
        sys.exit(f"modes_table: {e}")
