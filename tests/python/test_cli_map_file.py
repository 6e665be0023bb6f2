"""Map files from the command line (docs/map-files.md): session 1 of a preset saves its map;
session 2 (the same room from another standpoint, `synth --session 2`) starts turned away from it,
relocalizes within 30 frames of its first view of mapped structure, and, localization only, is
tracked in the world frame of map-file session 1 (judged with its alignment, no fit of its own)
without touching the map file; extending the map saves a larger one; bad map files stop the run
with one line."""
import hashlib
import json

import numpy as np
import pytest

from cli import lrdslam, synth_input

FRAMES = 180  # map-file session 2 turns towards the first session's view over its first 120 frames


def summary(out):
    return json.loads((out / "summary.json").read_text())


def digest(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture(scope="module")
def sessions(tmp_path_factory):
    d = tmp_path_factory.mktemp("sessions")
    for n in (1, 2):
        synth_input("--preset", "static_xyz", "--session", n, "--frames", FRAMES, "--out", d / f"s{n}")
    lrdslam("run", "--sequence", d / "s1", "--mode", "static", "--deterministic", "--quiet", "--out", d / "run1",
            "--save-map", d / "s1.lrdmap")
    return d


def ate_in_session_one_frame(d, out):
    r = lrdslam("eval", d / "s2" / "groundtruth.txt", out / "CameraTrajectory.txt", "--align-with",
                d / "s1" / "groundtruth.txt", d / "run1" / "CameraTrajectory.txt", "--json", "-")
    return json.loads(r.stdout)["ate"]


def test_session_two_localizes_in_session_ones_map(sessions, tmp_path):
    d = sessions
    before = digest(d / "s1.lrdmap")
    out = tmp_path / "loc"
    r = lrdslam("run", "--sequence", d / "s2", "--mode", "static", "--deterministic", "--quiet", "--out", out,
                "--load-map", d / "s1.lrdmap", "--localization-only")
    s = summary(out)
    m = s["map_file"]
    assert m["localization_only"] and m["loaded_keyframes"] == s["keyframes"] > 2, s
    assert s["map_points"] == m["loaded_map_points"], s
    # It starts turned away: not localized at first (a state, not a loss), then placed within 30
    # frames of the first frame that sees what the map holds.
    assert s["not_localized"] == m["first_localized_frame"] > 0, s
    assert m["first_view_frame"] is not None and m["first_view_frame"] > 0, m
    assert m["relocalization_frames"] <= 30, m
    # At the map's edge a frame or two may be lost again (no keyframes are added to hold it).
    assert s["tracked"] >= FRAMES - m["first_localized_frame"] - 10, s
    assert "localized in the loaded map at frame" in r.stdout
    ate = ate_in_session_one_frame(d, out)
    assert ate["rmse"] < 0.01 and ate["pairs"] == s["tracked"], ate
    assert digest(d / "s1.lrdmap") == before


def test_walking_session_two_localizes_within_two_centimetres_in_full_mode(tmp_path):
    # People walk through the mapped part of the room; both map-file sessions run `full`
    # (FNet + geometry).
    d = tmp_path
    for n in (1, 2):
        synth_input("--preset", "walking_xyz", "--session", n, "--frames", 160, "--out", d / f"s{n}")
    lrdslam("run", "--sequence", d / "s1", "--mode", "full", "--deterministic", "--quiet", "--out", d / "run1",
            "--save-map", d / "s1.lrdmap")
    out = d / "loc"
    lrdslam("run", "--sequence", d / "s2", "--mode", "full", "--deterministic", "--quiet", "--out", out,
            "--load-map", d / "s1.lrdmap", "--localization-only")
    s = summary(out)
    assert s["map_file"]["relocalization_frames"] <= 30 and s["tracked"] >= 60, s
    ate = ate_in_session_one_frame(d, out)
    assert ate["rmse"] < 0.02 and ate["pairs"] == s["tracked"], ate


def test_session_two_extends_the_map(sessions, tmp_path):
    d = sessions
    out = tmp_path / "ext"
    lrdslam("run", "--sequence", d / "s2", "--mode", "static", "--deterministic", "--quiet", "--out", out,
            "--load-map", d / "s1.lrdmap", "--save-map", tmp_path / "merged.lrdmap")
    s = summary(out)
    assert s["keyframes"] > s["map_file"]["loaded_keyframes"], s
    assert s["map_file"]["saved"] == str(tmp_path / "merged.lrdmap")
    assert (tmp_path / "merged.lrdmap").stat().st_size > (d / "s1.lrdmap").stat().st_size
    assert ate_in_session_one_frame(d, out)["rmse"] < 0.01
    # The merged map loads again, and session 1 is localized in it at once.
    out1 = tmp_path / "again"
    lrdslam("run", "--sequence", d / "s1", "--mode", "static", "--quiet", "--out", out1, "--load-map",
            tmp_path / "merged.lrdmap", "--localization-only", "--max-frames", 40)
    assert summary(out1)["map_file"]["first_localized_frame"] == 0


def test_a_second_session_closes_a_loop_into_the_old_map(tmp_path):
    # static_loop at 2.5x: one lap is 200 frames. Session 1 sees 130 frames of it and maps them;
    # map-file session 2 (0.58 m aside) relocalizes in that part, maps the rest of the lap and comes
    # back into it.
    for n, frames in ((1, 130), (2, 250)):
        synth_input("--preset", "static_loop", "--camera-speed", 2.5, "--session", n, "--frames", frames,
                "--out", tmp_path / f"s{n}")
    lrdslam("run", "--sequence", tmp_path / "s1", "--mode", "static", "--deterministic", "--quiet", "--out",
            tmp_path / "run1", "--save-map", tmp_path / "s1.lrdmap")
    s1 = summary(tmp_path / "run1")
    old_ids = s1["keyframes"] + s1["culled_keyframes"]  # ids of the old map: 0 .. old_ids - 1
    out = tmp_path / "run2"
    lrdslam("run", "--sequence", tmp_path / "s2", "--mode", "static", "--deterministic", "--quiet", "--out", out,
            "--load-map", tmp_path / "s1.lrdmap", "--save-map", tmp_path / "merged.lrdmap")
    s = summary(out)
    into_old = [l for l in s["loops"] if l["loop_keyframe"] < old_ids <= l["keyframe"]]
    assert into_old, (old_ids, s["loops"])
    ate = ate_in_session_one_frame(tmp_path, out)
    assert ate["rmse"] < 0.01 and ate["pairs"] == s["tracked"] == 250, (ate, s)


@pytest.mark.parametrize("case", ["truncated", "corrupted", "version", "camera", "not-a-map"])
def test_bad_map_files_stop_before_tracking(sessions, tmp_path, case):
    d = sessions
    good = (d / "s1.lrdmap").read_bytes()
    bad = tmp_path / f"{case}.lrdmap"
    args = []
    if case == "truncated":
        bad.write_bytes(good[:len(good) // 3])
        expected = "truncated map file"
    elif case == "corrupted":
        bad.write_bytes(good[:5000] + bytes([good[5000] ^ 0x40]) + good[5001:])
        expected = "checksum mismatch"
    elif case == "version":
        bad.write_bytes(good[:8] + bytes([7]) + good[9:])
        expected = "unsupported map file version 7"
    elif case == "camera":
        bad.write_bytes(good)
        args = ["--preset", "tum1"]
        expected = "the map's camera differs from this run's: fx"
    else:
        bad.write_text("hello")
        expected = "not an lrd-slam map file"
    out = tmp_path / "out"
    r = lrdslam("run", "--sequence", d / "s2", "--quiet", "--out", out, "--load-map", bad, *args, check=False)
    assert r.returncode != 0
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and f"{bad}: {expected}" in lines[0], r.stderr
    assert not (out / "CameraTrajectory.txt").exists()


def test_localization_only_needs_a_map(sessions, tmp_path):
    r = lrdslam("run", "--sequence", sessions / "s2", "--quiet", "--out", tmp_path, "--localization-only",
                check=False)
    assert r.returncode != 0 and "--localization-only needs a map to localize in (--load-map)" in r.stderr


def optical_axis(qx, qy, qz, qw):
    """The camera's viewing direction (its z axis) in the world, from a TUM quaternion."""
    return np.array([2 * (qx * qz + qw * qy), 2 * (qy * qz - qw * qx), 1 - 2 * (qx * qx + qy * qy)])


def test_sessions_two_and_three_start_elsewhere_in_the_same_world_frame(tmp_path):
    starts = []
    for n in (1, 2, 3):
        lrdslam("synth", "--preset", "walking_xyz", "--session", n, "--frames", 2, "--out", tmp_path / f"s{n}")
        rows = (tmp_path / f"s{n}" / "groundtruth.txt").read_text().splitlines()
        starts.append(np.array([float(v) for v in [l for l in rows if not l.startswith("#")][0].split()[1:8]]))
        assert json.loads((tmp_path / f"s{n}" / "sequence.json").read_text())["session"] == n
    # Sessions 2 and 3 start a step aside, turned about 80 deg away (left, right) from session 1.
    for n, side in ((1, 1), (2, -1)):
        assert np.linalg.norm(starts[n][:3] - starts[0][:3]) > 0.25, starts
        a, b = optical_axis(*starts[0][3:]), optical_axis(*starts[n][3:])
        turn = np.degrees(np.arctan2(np.cross(a[:2], b[:2]), np.dot(a[:2], b[:2])))
        assert 70 < side * turn < 90, (n, turn)
    r = lrdslam("synth", "--preset", "walking_xyz", "--session", 4, "--frames", 2, "--out", tmp_path / "x",
                check=False)
    assert r.returncode != 0
