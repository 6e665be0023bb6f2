"""Tracking that follows a person (docs/slam-core.md, "Moving faster than a camera"): in `static`
mode, nothing removes people, and where a person walking past fills much of the view tracking moves
the camera at their pace. Over tracking.max_camera_speed (over 0.2 s) the frame is tracked again
from the pose where that stride began (and kept so when that is within the limit), and the frames
that followed are placed again between the two; without the limit tracking stays with the person for
frames. The first 45 frames of walking_halfsphere do it twice."""
import json
import re

import numpy as np

from cli import lrdslam, synth_input

FRAMES = 45


def matrix(values):
    """Camera-to-world 4x4 from a TUM line's tx ty tz qx qy qz qw."""
    t, (x, y, z, w) = values[:3], values[3:]
    m = np.eye(4)
    m[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                 [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                 [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    m[:3, 3] = t
    return m


def poses(path):
    rows = [l.split() for l in path.read_text().splitlines() if l.strip() and not l.startswith("#")]
    return {r[0]: matrix([float(v) for v in r[1:8]]) for r in rows}


def centres(out):
    """Camera centres of the trajectory file, in its order."""
    return [m[:3, 3] for _, m in sorted(poses(out / "CameraTrajectory.txt").items(), key=lambda kv: float(kv[0]))]


def position_errors(sequence, out):
    """Frame index -> distance from the true camera centre, the estimate placed at the true first
    pose (the map's world is the first camera's): no alignment that could hide a jump."""
    stamps = [l.split()[0] for l in (sequence / "associations.txt").read_text().splitlines() if not l.startswith("#")]
    truth = poses(sequence / "groundtruth.txt")
    true_stamps = sorted(truth, key=float)

    def true_pose(stamp):
        return truth[min(true_stamps, key=lambda t: abs(float(t) - float(stamp)))]

    estimate = poses(out / "CameraTrajectory.txt")
    first = true_pose(stamps[0])
    return {k: float(np.linalg.norm((first @ estimate[s])[:3, 3] - true_pose(s)[:3, 3]))
            for k, s in enumerate(stamps) if s in estimate}


def test_tracking_that_follows_a_person_is_tracked_again_from_where_its_stride_began(tmp_path):
    sequence = tmp_path / "walking_halfsphere"
    synth_input("--preset", "walking_halfsphere", "--frames", FRAMES, "--out", sequence)
    (tmp_path / "no_limit.yaml").write_text("tracking:\n  max_camera_speed: 0\n")

    def run(out, *config):
        r = lrdslam("run", "--sequence", sequence, "--mode", "static", "--deterministic", "--quiet",
                    "--out", tmp_path / out, *config)
        summary = json.loads((tmp_path / out / "summary.json").read_text())
        return r.stdout + r.stderr, position_errors(sequence, tmp_path / out), summary

    log, limited, summary = run("limited")
    strides = [(int(start), int(f)) for f, start in re.findall(
        r"frame (\d+): tracking moved the camera [\d.]+ m in [\d.]+ s .*; it "
        r"followed something that moves: tracked again from frame (\d+)'s pose", log)]
    again = [f for _, f in strides]
    print("tracked again:", again, "errors:", [round(limited[f], 3) for f in again])
    assert len(again) >= 1, log
    assert summary["implausible_camera_motions"] >= len(again)
    assert summary["tracked"] == FRAMES
    for f in again:
        assert limited[f] < 0.05, (f, limited[f])

    _, free, free_summary = run("free", "--config", tmp_path / "no_limit.yaml")
    assert free_summary["implausible_camera_motions"] == 0
    # Without the limit the same frames are still with the person.
    print("without a limit:", [round(free[f], 3) for f in again])
    assert max(free[f] for f in again) > 0.1
    # The frames that followed the person are placed again between the two poses the map agrees
    # with: no step from the stride's start to the frame after the one tracked again, and the run
    # stays within 12 cm where without the limit it strays 20 cm and more. (Elsewhere a step is
    # no fault of the limit: in `static` mode a person drags a keyframe, and the frames placed on it
    # step when the next keyframe is right; frame 17 here steps 7 cm back to within 1 cm of the truth.)
    print("largest error:", round(max(limited.values()), 3), "without a limit:", round(max(free.values()), 3))
    assert max(limited.values()) < 0.12
    assert max(free.values()) > 0.2
    c = centres(tmp_path / "limited")
    steps = [float(np.linalg.norm(c[k + 1] - c[k]))
             for start, f in strides for k in range(start, min(f + 1, len(c) - 1))]
    print("largest step over the strides tracked again:", round(max(steps), 3))
    assert max(steps) < 0.06
