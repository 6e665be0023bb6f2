"""`lrdslam eval` against a line-by-line Python port of TUM's evaluate_ate.py / evaluate_rpe.py
(tests/python/reference/tum_evaluate.py) on random trajectories: every ATE and RPE statistic must
agree to 1e-6 and the pair counts exactly."""
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent / "reference"))
import tum_evaluate  # noqa: E402

LRDSLAM_BIN = os.environ.get("LRDSLAM_BIN")
pytestmark = pytest.mark.skipif(
    not LRDSLAM_BIN, reason="LRDSLAM_BIN is not set (path of the lrdslam CLI; ctest sets it)")

STATS = ("rmse", "mean", "median", "std", "min", "max")
METRICS = ("ate", "rpe_trans", "rpe_rot")
TOL = 1e-6


# ---- random trajectories -------------------------------------------------------------------

def quat_from_rotvec(w):
    angle = np.linalg.norm(w)
    if angle < 1e-12:
        return np.array([0.0, 0.0, 0.0, 1.0])
    axis = w / angle
    return np.concatenate([axis * math.sin(angle / 2), [math.cos(angle / 2)]])  # qx qy qz qw


def quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array([aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw,
                     aw * bw - ax * bx - ay * by - az * bz])


def rotate(q, v):
    qv = np.concatenate([v, [0.0]])
    conj = np.array([-q[0], -q[1], -q[2], q[3]])
    return quat_mul(quat_mul(q, qv), conj)[:3]


def gt_pose(t):
    """A smooth hand-held-like camera motion (camera-to-world)."""
    p = np.array([1.5 * math.sin(0.4 * t), 0.8 * math.cos(0.3 * t) + 0.05 * t, 1.2 + 0.3 * math.sin(0.7 * t)])
    w = np.array([0.3 * math.sin(0.5 * t), 0.2 * t, 0.2 * math.cos(0.3 * t)])
    return p, quat_from_rotvec(w)


def stamps(rng, start, duration, rate, jitter=0.0, gaps=()):
    t = start + np.arange(int(duration * rate)) / rate
    if jitter:
        t = t + rng.uniform(-jitter, jitter, size=t.shape)
    keep = np.ones(t.shape, dtype=bool)
    for a, b in gaps:
        keep &= ~((t >= start + a) & (t < start + b))
    return np.sort(t[keep])


def write_tum(path, rows, sep=" ", fmt="%.9f", header=True, blank_lines=False, newline="\n"):
    lines = ["# timestamp tx ty tz qx qy qz qw"] if header else []
    for k, (t, p, q) in enumerate(rows):
        values = ["%.6f" % t] + [fmt % v for v in list(p) + list(q)]
        lines.append(sep.join(values))
        if blank_lines and k % 50 == 25:
            lines.append("")
            lines.append("# a comment in the middle")
    path.write_text(newline.join(lines) + newline)


def make_case(tmp_path, name, seed, gt_rate=100.0, est_rate=30.0, duration=8.0, offset=0.0, jitter=0.0,
              gt_gaps=(), est_gaps=(), noise_t=0.01, noise_r=0.01, drift=0.02, irregular=False, mirror=False,
              denormalize=False, invalid_lines=False, sep=" ", fmt="%.9f", blank_lines=False, newline="\n",
              start=None):
    rng = np.random.default_rng(seed)
    start_draw = 1305031102.0 + rng.uniform(0, 10)
    start = start_draw if start is None else start
    gt_t = stamps(rng, start, duration, gt_rate, gaps=gt_gaps)
    if irregular:
        est_t = np.sort(rng.uniform(start, start + duration, size=int(duration * est_rate)))
    else:
        est_t = stamps(rng, start + offset, duration, est_rate, jitter=jitter, gaps=est_gaps)
    est_t = np.unique(np.round(est_t, 6))

    gt_rows = [(t, *gt_pose(t - start)) for t in np.round(gt_t, 6)]
    # The estimate lives in its own world frame: a fixed rigid offset the alignment must undo.
    world_q = quat_from_rotvec(rng.normal(size=3))
    world_t = rng.normal(size=3)
    est_rows = []
    for t in est_t:
        p, q = gt_pose(t - start)
        p = p + rng.normal(scale=noise_t, size=3) + np.array([drift, -0.5 * drift, 0.3 * drift]) * (t - start)
        q = quat_mul(q, quat_from_rotvec(rng.normal(scale=noise_r, size=3) + 0.02 * drift * (t - start)))
        if mirror:
            p = p * np.array([-1.0, 1.0, 1.0])
        p = rotate(world_q, p) + world_t
        q = quat_mul(world_q, q)
        if denormalize:
            q = q * rng.uniform(0.3, 3.0) * rng.choice([-1.0, 1.0])
        est_rows.append((t, p, q))
    if invalid_lines:
        # Entries evaluate_rpe.py drops: an all-zero quaternion, a NaN.
        est_rows.insert(40, (est_t[40] + 1e-4, np.array([1.0, 2.0, 3.0]), np.zeros(4)))
        est_rows.insert(80, (est_t[80] + 1e-4, np.array([float("nan"), 2.0, 3.0]), np.array([0, 0, 0, 1.0])))
    gt_file = tmp_path / f"{name}_gt.txt"
    est_file = tmp_path / f"{name}_est.txt"
    write_tum(gt_file, gt_rows)
    write_tum(est_file, est_rows, sep=sep, fmt=fmt, blank_lines=blank_lines, newline=newline)
    return gt_file, est_file


CASES = {
    "tum_rates": dict(seed=1, gt_rate=100.0, est_rate=30.0, offset=0.004),
    "same_rate_gaps_commas": dict(seed=2, gt_rate=30.0, est_rate=30.0, duration=12.0, jitter=0.005,
                                  gt_gaps=((3.0, 3.6), (7.0, 9.5)), est_gaps=((5.0, 6.2),), sep=", "),
    "tabs_comments_denormalized_invalid": dict(seed=3, gt_rate=50.0, est_rate=20.0, duration=15.0, offset=0.011,
                                               sep="\t", blank_lines=True, denormalize=True, invalid_lines=True),
    "irregular_big_drift": dict(seed=4, gt_rate=60.0, est_rate=25.0, duration=10.0, irregular=True, drift=0.2,
                                noise_r=0.05, fmt="%.17g"),
    "mirrored_crlf": dict(seed=5, gt_rate=100.0, est_rate=15.0, duration=20.0, mirror=True, newline="\r\n",
                          noise_t=0.05),
    "large_rotation_noise": dict(seed=6, gt_rate=30.0, est_rate=30.0, duration=10.0, jitter=0.012, noise_r=0.3,
                                 noise_t=0.1),
}


# ---- helpers ------------------------------------------------------------------------------------

def run_cli(*args):
    return subprocess.run([LRDSLAM_BIN, "eval", *map(str, args)], capture_output=True, text=True, timeout=120)


def run_json(tmp_path, *args):
    out = tmp_path / "result.json"
    proc = run_cli(*args, "--json", out)
    assert proc.returncode == 0, proc.stderr
    return json.loads(out.read_text()), proc.stdout


def assert_matches_reference(ours, ref):
    for metric in METRICS:
        assert ours[metric]["pairs"] == ref[metric]["pairs"], metric
        for stat in STATS:
            assert ours[metric][stat] == pytest.approx(ref[metric][stat], abs=TOL, rel=0), f"{metric}.{stat}"


# ---- tests --------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", sorted(CASES))
def test_eval_matches_tum_reference(tmp_path, name):
    gt_file, est_file = make_case(tmp_path, name, **CASES[name])
    ref = tum_evaluate.evaluate(gt_file, est_file)
    assert 100 <= ref["ate"]["pairs"]  # a few hundred poses, not a toy
    ours, stdout = run_json(tmp_path, gt_file, est_file)
    assert_matches_reference(ours, ref)
    assert "no random subsampling" in stdout


def test_eval_options_match_reference(tmp_path):
    gt_file, est_file = make_case(tmp_path, "opts", seed=7, gt_rate=30.0, est_rate=30.0, duration=12.0,
                                  jitter=0.008, noise_r=0.05)
    ref = tum_evaluate.evaluate(gt_file, est_file, max_difference=0.005, delta=0.5)
    ours, _ = run_json(tmp_path, gt_file, est_file, "--max-dt", "0.005", "--delta", "0.5")
    assert_matches_reference(ours, ref)
    assert ours["ate"]["pairs"] < len(tum_evaluate.read_file_list(est_file))  # the tighter window bites


def test_reference_port_skips_invalid_entries_like_evaluate_rpe(tmp_path):
    gt_file, est_file = make_case(tmp_path, "invalid", seed=8, invalid_lines=True)
    traj = tum_evaluate.read_trajectory(est_file)
    assert len(traj) == len(tum_evaluate.read_file_list(est_file)) - 2


def test_compare_improvement_matches_reference(tmp_path):
    # Same start time, hence the same ground truth, for both runs.
    common = dict(gt_rate=50.0, est_rate=30.0, duration=10.0, offset=0.003, start=1305031105.25)
    gt_file, base_file = make_case(tmp_path, "base", seed=9, noise_t=0.05, noise_r=0.05, drift=0.1, **common)
    _, ours_file = make_case(tmp_path, "ours", seed=10, noise_t=0.01, noise_r=0.01, drift=0.02, **common)
    ref_base = tum_evaluate.evaluate(gt_file, base_file)
    ref_ours = tum_evaluate.evaluate(gt_file, ours_file)

    result, stdout = run_json(tmp_path, "--compare", base_file, ours_file, gt_file)
    assert_matches_reference(result["baseline"], ref_base)
    assert_matches_reference(result["ours"], ref_ours)
    for metric in METRICS:
        for stat in STATS:
            o, r = ref_base[metric][stat], ref_ours[metric][stat]
            eta = (o - r) / o * 100.0
            assert result["improvement_percent"][metric][stat] == pytest.approx(eta, rel=1e-6, abs=1e-6), \
                f"{metric}.{stat}"
    assert result["improvement_percent"]["ate"]["rmse"] > 0  # ours is the less noisy one

    # The printed table: under each metric, "  stat  baseline  ours  eta".
    sections = {"ATE": "ate", "RPE trans": "rpe_trans", "RPE rot": "rpe_rot"}
    metric = None
    seen = 0
    for line in stdout.splitlines():
        head = next((m for prefix, m in sections.items() if line.startswith(prefix)), None)
        if head:
            metric = head
            continue
        fields = line.split()
        if metric and len(fields) == 4 and fields[0] in STATS:
            base, ours, eta = map(float, fields[1:])
            o, r = ref_base[metric][fields[0]], ref_ours[metric][fields[0]]
            assert base == pytest.approx(o, abs=1e-6)
            assert ours == pytest.approx(r, abs=1e-6)
            assert eta == pytest.approx((o - r) / o * 100.0, abs=0.006)
            seen += 1
    assert seen == len(STATS) * len(METRICS), stdout


def test_eval_writes_plots(tmp_path):
    gt_file, est_file = make_case(tmp_path, "plot", seed=11)
    proc = run_cli(gt_file, est_file, "--plot", tmp_path / "plots")
    assert proc.returncode == 0, proc.stderr
    for name in ("trajectory_top.png", "ape_over_time.png"):
        data = (tmp_path / "plots" / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n", name


def test_eval_errors_are_one_line(tmp_path):
    gt_file, est_file = make_case(tmp_path, "err", seed=12)
    missing = tmp_path / "missing.txt"
    proc = run_cli(gt_file, missing)
    assert proc.returncode == 1
    assert proc.stderr.startswith("error: ") and str(missing) in proc.stderr
    assert proc.stderr.count("\n") == 1

    bad = tmp_path / "bad.txt"
    bad.write_text("# header\n1.0 0 0 0 0 0 0 1\n2.0 0 0 zero 0 0 0 1\n")
    proc = run_cli(gt_file, bad)
    assert proc.returncode == 1 and f"{bad}:3:" in proc.stderr

    far = tmp_path / "far.txt"
    write_tum(far, [(1000.0 + k, np.zeros(3), np.array([0, 0, 0, 1.0])) for k in range(10)])
    proc = run_cli(gt_file, far)
    assert proc.returncode == 1 and str(far) in proc.stderr and proc.stderr.count("\n") == 1
