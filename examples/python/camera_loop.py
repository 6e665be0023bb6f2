#!/usr/bin/python3
"""Feed lrd-slam frames from your own code: a camera loop. Here the "camera" is a function that
returns numpy images (the synthetic benchmark's frames; put your driver's read() there), stamped
with the time it delivered them. Events arrive on lrd-slam's publisher thread.

    PYTHONPATH=build/release/python examples/python/camera_loop.py [--frames 200]
"""
import argparse
import time

import numpy as np

import lrdslam


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--frames", type=int, default=200)
    args = p.parse_args()
    rendered = lrdslam.synth.render("walking_static", frames=args.frames)

    def grab(i):  # your camera: colour HxWx3 uint8 (RGB), depth HxW uint16 millimetres or float32 metres
        f = rendered[i]
        return f.rgb, (f.depth * 1000).astype(np.uint16)

    keyframes = []
    # The camera's intrinsics and depth unit: a config as a dict (the same keys as config/default.yaml).
    slam = lrdslam.System({"camera": {"preset": "tum3", "depth_map_factor": 1000.0}}, mode="geometric")
    slam.subscribe(lambda e: keyframes.append(e.keyframe_id) if e.kind == "keyframe" else None)
    t0 = time.monotonic()
    for i in range(args.frames):
        rgb, depth = grab(i)
        r = slam.track_rgbd(rgb, depth, time.monotonic() - t0)
        if i % 50 == 0:
            where = "lost" if r.pose is None else np.array2string(r.pose[:3, 3], precision=3)
            print(f"frame {i}: {r.state}, {r.inliers} inliers, camera at {where}, "
                  f"{r.timing['total'] * 1000:.1f} ms")
    slam.shutdown()
    print(f"{len(keyframes)} keyframes, {slam.map_stats()['map_points']} map points")


if __name__ == "__main__":
    main()
