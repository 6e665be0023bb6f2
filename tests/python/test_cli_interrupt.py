"""SIGINT / SIGTERM during `lrdslam run` (a real process, a real signal): the run stops reading
frames, finishes the queued work, writes the trajectories and summary.json with
"interrupted": true and the frames done, and exits 130; a second SIGINT exits at once."""
import json
import signal
import subprocess
import time

import pytest

from cli import BIN, lrdslam, synth_input

FRAMES = 150


@pytest.fixture(scope="module")
def sequence(tmp_path_factory):
    d = tmp_path_factory.mktemp("seq") / "static_xyz"
    synth_input("--preset", "static_xyz", "--frames", FRAMES, "--out", d)
    return d


def start_run(sequence, out):
    # --realtime: 30 frames a second, so the run lasts ~5 s and the signal lands in the middle.
    return subprocess.Popen([BIN, "run", "--sequence", str(sequence), "--out", str(out), "--realtime", "--quiet",
                             "--no-loop-closing"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def wait_for_frames(proc, seconds=3.0):
    """Lets the run get past its start (vocabulary, first frames) and asserts it is still going."""
    time.sleep(seconds)
    assert proc.poll() is None, "the run ended before it could be interrupted"


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_an_interrupt_writes_every_output_from_the_frames_done(sequence, tmp_path, sig):
    out = tmp_path / "out"
    proc = start_run(sequence, out)
    wait_for_frames(proc)
    proc.send_signal(sig)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 130, stdout + stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["interrupted"] is True
    assert 0 < summary["frames"] < FRAMES
    poses = [l for l in (out / "CameraTrajectory.txt").read_text().splitlines() if l and not l.startswith("#")]
    assert len(poses) == summary["tracked"]
    assert summary["tracked"] >= summary["frames"] - 5
    times = [l for l in (out / "track_times.txt").read_text().splitlines() if not l.startswith("#")]
    assert len(times) == summary["frames"]
    assert (out / "KeyFrameTrajectory.txt").stat().st_size > 0
    assert "interrupted after" in stderr
    for word in ("AddressSanitizer", "runtime error", "terminate called"):
        assert word not in stderr


def test_a_second_interrupt_quits_at_once(sequence, tmp_path):
    out = tmp_path / "out"
    proc = start_run(sequence, out)
    wait_for_frames(proc)
    proc.send_signal(signal.SIGINT)
    proc.send_signal(signal.SIGINT)
    t0 = time.monotonic()
    proc.communicate(timeout=60)
    assert proc.returncode == 130
    assert time.monotonic() - t0 < 5.0


def test_an_uninterrupted_run_says_so(sequence, tmp_path):
    out = tmp_path / "out"
    lrdslam("run", "--sequence", sequence, "--out", out, "--quiet", "--max-frames", 20, "--no-loop-closing")
    assert json.loads((out / "summary.json").read_text())["interrupted"] is False
