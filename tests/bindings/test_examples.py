"""examples/python/ as a user runs them."""
import filecmp
import os
import re
import subprocess
import sys

from conftest import cli

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "python")


def example(name, *args):
    r = subprocess.run([sys.executable, os.path.join(EXAMPLES, name), *map(str, args)], capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0, f"{name} failed:\n{r.stdout}\n{r.stderr}"
    return r.stdout


def test_track_folder_writes_the_clis_trajectory(walking, tmp_path):
    out = example("track_folder.py", walking, tmp_path / "py", "--mode", "geometric", "--deterministic")
    cli("run", "--sequence", walking, "--mode", "geometric", "--deterministic", "--out", tmp_path / "cli", "--quiet")
    assert filecmp.cmp(tmp_path / "py" / "CameraTrajectory.txt", tmp_path / "cli" / "CameraTrajectory.txt",
                       shallow=False)
    assert float(re.search(r"ATE RMSE ([\d.]+) cm", out).group(1)) < 2.0


def test_modes_table_prints_every_mode():
    out = example("modes_table.py", "--preset", "walking_xyz", "--frames", 40, "--modes", "static,geometric",
                  "--deterministic")
    rows = {line.split()[0]: line.split() for line in out.splitlines() if line.split()[:1] in (["static"], ["geometric"])}
    assert set(rows) == {"static", "geometric"}
    assert float(rows["geometric"][1]) < float(rows["static"][1])  # the check helps with people walking
    assert rows["geometric"][-1].endswith("%")


def test_camera_loop_tracks_its_own_frames():
    out = example("camera_loop.py", "--frames", 60)
    assert "frame 50: ok" in out
    assert int(re.search(r"(\d+) keyframes", out).group(1)) >= 2
