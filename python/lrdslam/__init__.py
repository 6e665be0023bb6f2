"""lrd-slam from Python: RGB-D SLAM for scenes with people, numpy in and out.

    import lrdslam
    seq = lrdslam.io.read_sequence("rgbd_dataset_freiburg3_walking_xyz")
    with lrdslam.System(sequence=seq, mode="full") as slam:
        for f in seq:
            r = slam.track_rgbd(f.rgb, f.depth, f.timestamp)
    print(lrdslam.eval.ate(seq.ground_truth, slam.trajectory()).rmse)

The API and what each call costs: docs/python.md.
"""
from ._core import Error, System, TrackResult, __version__
from . import eval, events, io, synth

__all__ = ["Error", "System", "TrackResult", "__version__", "eval", "events", "io", "synth"]
