"""lrdslam.System through Python against the CLI, and its maps."""
import filecmp

import numpy as np
import pytest

import lrdslam
from conftest import cli


def track_all(slam, seq):
    results = []
    for f in seq:
        results.append(slam.track_rgbd(f.rgb, f.depth, f.timestamp))
    slam.shutdown()
    return results


def test_deterministic_run_equals_the_cli_byte_for_byte(walking, tmp_path):
    out = tmp_path / "cli"
    cli("run", "--sequence", walking, "--mode", "full", "--deterministic", "--out", out, "--quiet")
    seq = lrdslam.io.read_sequence(walking)
    slam = lrdslam.System(sequence=walking, mode="full", deterministic=True)
    assert slam.mode == "full" and "fnet" in slam.segmentation
    results = track_all(slam, seq)
    slam.save_trajectory(tmp_path / "py.txt")
    assert filecmp.cmp(tmp_path / "py.txt", out / "CameraTrajectory.txt", shallow=False)
    # trajectory() holds the same poses as the file (written with 9 decimals).
    written = np.loadtxt(out / "CameraTrajectory.txt")
    traj = slam.trajectory()
    assert traj.shape == written.shape and traj.shape[1] == 8
    np.testing.assert_allclose(traj, written, atol=1e-6)
    ok = [r for r in results if r.state == "ok"]
    assert len(ok) >= 55
    assert all(r.pose.shape == (4, 4) and np.allclose(r.pose[3], [0, 0, 0, 1]) for r in ok)
    # A pose is the trajectory's row at that frame's stamp (camera to world).
    last = ok[-1].pose
    row = traj[-1]
    np.testing.assert_allclose(last[:3, 3], row[1:4], atol=2e-3)
    # The run is accurate: ATE against the sequence's ground truth.
    assert lrdslam.eval.ate(seq.ground_truth, traj).rmse < 0.02


def test_eval_equals_lrdslam_eval(walking, tmp_path):
    out = tmp_path / "run"
    cli("run", "--sequence", walking, "--mode", "geometric", "--out", out, "--quiet")
    import json
    printed = json.loads(cli("eval", walking / "groundtruth.txt", out / "CameraTrajectory.txt", "--json", "-").stdout)
    ate = lrdslam.eval.ate(walking / "groundtruth.txt", out / "CameraTrajectory.txt")
    rpe = lrdslam.eval.rpe(str(walking / "groundtruth.txt"), str(out / "CameraTrajectory.txt"))
    for key in ("rmse", "mean", "median", "std", "min", "max", "pairs"):
        assert getattr(ate, key) == printed["ate"][key]
        assert getattr(rpe.trans, key) == printed["rpe_trans"][key]
        assert getattr(rpe.rot, key) == printed["rpe_rot"][key]
    # Arrays give the same numbers as the files they were read from.
    est = np.loadtxt(out / "CameraTrajectory.txt")
    assert lrdslam.eval.ate(lrdslam.io.read_sequence(walking).ground_truth, est).rmse == pytest.approx(ate.rmse, rel=1e-6)


def test_maps_snapshots_and_map_files(walking, tmp_path):
    seq = lrdslam.io.read_sequence(walking)
    slam = lrdslam.System(sequence=walking, mode="geometric", dense=True, occupancy=True, deterministic=True)
    track_all(slam, seq)
    stats = slam.map_stats()
    snap = slam.map_snapshot()
    assert snap.keyframe_poses.shape == (stats["keyframes"], 4, 4) and stats["keyframes"] >= 2
    assert snap.points.shape == (stats["map_points"], 3) and snap.points.shape[0] > 100
    assert len(snap.point_ids) == len(snap.points) and len(set(snap.point_ids.tolist())) == len(snap.points)
    assert np.all(np.diff(snap.keyframe_timestamps) > 0)
    dense = slam.dense_map()
    assert dense.points.shape[0] > 1000 and dense.points.shape[1] == 3 and dense.points.dtype == np.float32
    assert dense.colours.shape == dense.points.shape and dense.colours.dtype == np.uint8
    occ = slam.occupancy()
    assert occ.grid.ndim == 2 and occ.grid.dtype == np.int8 and occ.resolution > 0
    assert set(np.unique(occ.grid).tolist()) <= {-1, 0, 100} and (occ.grid == 100).any() and (occ.grid == 0).any()
    slam.save_map(tmp_path / "room.lrdmap")
    assert (tmp_path / "room.lrdmap").stat().st_size > 1000
    # A second system localizes in the saved map.
    again = lrdslam.System(sequence=walking, mode="geometric", localization_only=True)
    again.load_map(tmp_path / "room.lrdmap")
    assert again.map_stats()["loaded_keyframes"] == stats["keyframes"]
    states = [again.track_rgbd(f.rgb, f.depth, f.timestamp).state for f in list(seq)[:10]]
    again.shutdown()
    assert states.count("ok") >= 8


def test_reset_starts_a_new_map(walking):
    seq = lrdslam.io.read_sequence(walking)
    with lrdslam.System(sequence=walking, mode="static") as slam:
        for f in list(seq)[:20]:
            slam.track_rgbd(f.rgb, f.depth, f.timestamp)
        assert len(slam.trajectory()) >= 18
        slam.reset()
        assert len(slam.trajectory()) == 0
        for f in list(seq)[20:30]:
            slam.track_rgbd(f.rgb, f.depth, f.timestamp)
        traj = slam.trajectory()
    assert 8 <= len(traj) <= 10 and traj[0, 0] >= seq[20].timestamp


def test_synth_render_equals_the_written_frames(walking):
    import cv2
    seq = lrdslam.synth.render("walking_xyz", frames=60)
    assert len(seq) == 60 and seq.synthetic and "walking_xyz" in lrdslam.synth.presets()
    for i in (0, 37):
        f = seq[i]
        png = cv2.imread(str(walking / f.rgb_path), cv2.IMREAD_COLOR)
        np.testing.assert_array_equal(f.rgb, png[:, :, ::-1])
        raw = cv2.imread(str(walking / f.depth_path), cv2.IMREAD_UNCHANGED)
        np.testing.assert_array_equal(f.depth, (raw / np.float32(5000.0)).astype(np.float32))
    written = lrdslam.io.read_sequence(walking)
    np.testing.assert_allclose(seq.timestamps, written.timestamps, rtol=0, atol=1e-6)  # rgb.txt: 6 decimals
    np.testing.assert_allclose(seq.ground_truth[:, 1:4], np.loadtxt(walking / "groundtruth.txt")[:, 1:4], atol=1e-9)


@pytest.mark.parametrize("suffix", [".bag", ".mcap", ".db3"])
def test_read_sequence_reads_a_bag_as_the_folder(walking, tmp_path, suffix):
    import subprocess
    from conftest import BIN
    bag = tmp_path / ("walking" + suffix)
    r = subprocess.run([BIN, "synth", "--preset", "walking_xyz", "--frames", "12", "--out", tmp_path / "seq",
                        "--bag", bag], capture_output=True, text=True)
    if r.returncode != 0 and "without ROS" in r.stderr:
        pytest.skip("this build has no ROS 1: " + r.stderr.strip())
    assert r.returncode == 0, r.stderr
    from_bag = lrdslam.io.read_sequence(bag, gt_from_tf="/world:/kinect")
    from_folder = lrdslam.io.read_sequence(tmp_path / "seq")
    assert len(from_bag) == len(from_folder) == 12
    assert from_bag.camera["fx"] == pytest.approx(535.4) and from_folder.camera is None
    assert from_bag.path == str(bag)
    for i in (0, 11):
        np.testing.assert_array_equal(from_bag[i].rgb, from_folder[i].rgb)
        np.testing.assert_allclose(from_bag[i].depth, from_folder[i].depth, atol=1e-6)
    np.testing.assert_allclose(from_bag.ground_truth[:, 1:], from_folder.ground_truth[:, 1:], atol=1e-6)
