"""A map that survives the process (`run --autosave`): runs killed with SIGKILL at 20 moments, half
of them while a save is being written (its temporary beside the file exists), leave every time a
map file that loads (`lrdslam map info`, every check of a run's --load-map) and a trajectory file
that parses: the last complete save, never a partial one; a run restarted on the autosaved map
goes on in the same map frame; --autosave without --save-map is one line."""
import json
import os
import signal
import subprocess
import time

import pytest

from cli import BIN, lrdslam, synth_input

FRAMES = 400
KILLS = 20


@pytest.fixture(scope="module")
def sequence(tmp_path_factory):
    d = tmp_path_factory.mktemp("autosave")
    synth_input("--preset", "static_xyz", "--frames", FRAMES, "--out", d / "seq")
    return d / "seq"


def partials(out):
    return [p for p in os.listdir(out) if p.endswith(".partial")]


def wait_for(predicate, proc, timeout):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return True
        if proc.poll() is not None:
            return False
        time.sleep(0.0005)
    return False


def saved_poses(out):
    try:
        return sum(1 for line in (out / "CameraTrajectory.txt").read_text().splitlines() if line[:1].isdigit())
    except FileNotFoundError:
        return 0


def killed_run(sequence, out, during_save, delay, min_poses=1):
    """Starts a run that autosaves every 0.05 s and kills it with SIGKILL once a save of at least
    `min_poses` poses is complete: at the next moment a save's temporary exists (during_save),
    else `delay` s later. Returns whether a save was being written at the kill."""
    out.mkdir()
    proc = subprocess.Popen([BIN, "run", "--sequence", sequence, "--mode", "static", "--quiet", "--out", out,
                             "--save-map", out / "map.lrdmap", "--autosave", "0.05"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        assert wait_for(lambda: (out / "map.lrdmap").exists() and saved_poses(out) >= min_poses, proc, 300), \
            f"no autosave before the run ended: {proc.stderr.read().decode()}"
        if during_save:
            wait_for(lambda: partials(out), proc, 30)
        else:
            time.sleep(delay)
        saving = bool(partials(out))
        proc.send_signal(signal.SIGKILL)
        assert proc.wait(30) == -signal.SIGKILL, "the run ended before it was killed"
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return saving


def check_trajectory(path):
    text = path.read_text()
    assert text.endswith("\n"), f"{path}: no newline at the end (a partial write)"
    poses = [line.split() for line in text.splitlines() if line and not line.startswith("#")]
    assert poses, f"{path}: no poses"
    for fields in poses:
        assert len(fields) == 8, f"{path}: a line of {len(fields)} fields"
        [float(v) for v in fields]
    return len(poses)


def test_runs_killed_at_twenty_moments_leave_the_last_complete_save(sequence, tmp_path):
    during = 0
    for k in range(KILLS):
        out = tmp_path / f"kill{k}"
        during += killed_run(sequence, out, during_save=k % 2 == 0, delay=0.05 * k)
        r = lrdslam("map", "info", out / "map.lrdmap")
        keyframes = int(r.stdout.split(": ")[1].split()[0])
        assert keyframes >= 1, r.stdout
        check_trajectory(out / "CameraTrajectory.txt")
        # What a kill leaves besides: at most the temporaries of the save it interrupted.
        assert set(os.listdir(out)) - set(partials(out)) <= {"map.lrdmap", "CameraTrajectory.txt"}, os.listdir(out)
    # Most of the kills aimed at a save hit one (a save can finish between the poll and the kill).
    assert during >= KILLS // 4, during


def test_a_restart_on_the_autosaved_map_goes_on_in_the_same_map_frame(sequence, tmp_path):
    first = tmp_path / "first"
    killed_run(sequence, first, during_save=False, delay=0.0, min_poses=60)
    poses = check_trajectory(first / "CameraTrajectory.txt")
    assert poses >= 60, poses
    second = tmp_path / "second"
    lrdslam("run", "--sequence", sequence, "--mode", "static", "--quiet", "--out", second, "--load-map",
            first / "map.lrdmap", "--max-frames", 150)
    summary = json.loads((second / "summary.json").read_text())
    assert summary["map_file"]["loaded_keyframes"] >= 1 and summary["tracked"] >= 140, summary
    # The same frames, as the killed run saved them and as the restarted run tracked them, compared
    # as they are (aligning the saved trajectory with itself: the identity, no fit): the restarted
    # run's poses are in the first run's map frame.
    saved = first / "CameraTrajectory.txt"
    r = lrdslam("eval", saved, second / "CameraTrajectory.txt", "--align-with", saved, saved, "--json", "-")
    ate = json.loads(r.stdout)["ate"]
    assert ate["rmse"] < 0.02 and ate["pairs"] >= min(poses, 150) - 10, ate


def test_autosave_needs_a_map_file(sequence, tmp_path):
    r = lrdslam("run", "--sequence", sequence, "--quiet", "--out", tmp_path / "o", "--autosave", "1", check=False)
    assert r.returncode != 0
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "--autosave" in lines[0] and "--save-map" in lines[0], r.stderr
