"""Running the lrdslam CLI from the tests (ctest sets LRDSLAM_BIN to the build's binary)."""
import json
import os
import re
import subprocess

BIN = os.environ.get("LRDSLAM_BIN", "build/release/bin/lrdslam")


def _run(binary, args, check):
    r = subprocess.run([binary, *map(str, args)], capture_output=True, text=True)
    if check and r.returncode != 0:
        raise AssertionError(f"lrdslam {' '.join(map(str, args))} failed:\n{r.stdout}\n{r.stderr}")
    return r


def lrdslam(*args, check=True):
    """Runs `lrdslam ARGS`; with check, a non-zero exit fails the test with its output."""
    return _run(BIN, args, check)


def _fixture_bin():
    """The binary that renders the tests' input sequences: the release build when ctest names one
    (LRDSLAM_FIXTURE_BIN) that is at least as new as the binary under test; rendering under ASan
    takes several times longer and the renderer has its own tests (test_cli_synth.py, SynthPresets)."""
    fixture = os.environ.get("LRDSLAM_FIXTURE_BIN")
    if fixture and os.access(fixture, os.X_OK) and os.path.exists(BIN) and \
            os.path.getmtime(fixture) >= os.path.getmtime(BIN):
        return fixture
    return BIN


def synth_input(*args):
    """`lrdslam synth ARGS` for a test's input sequence (not for testing synth itself)."""
    return _run(_fixture_bin(), ("synth", *args), True)


def page_data(html):
    """The data a report page (lrdslam report) carries in its #report-data script."""
    m = re.search(r'<script type="application/json" id="report-data">(.*?)</script>', html, re.S)
    assert m, "no report data in the page"
    return json.loads(m.group(1))


def run_bag_and_folder(folder, bag, out, frames, *run_args):
    """`lrdslam run` on a sequence folder and on the bag of the same frames (ground truth from /tf),
    both into OUT/folder and OUT/bag; asserts the bag's camera came from its camera_info, the two
    trajectories are byte-identical with a pose per frame, and so are their ATEs. Returns the bag
    run's summary.json."""
    lrdslam("run", "--sequence", folder, "--out", out / "folder", *run_args)
    r = lrdslam("run", "--bag", bag, "--gt-from-tf", "/world:/kinect", "--out", out / "bag", *run_args)
    assert "camera: camera_info /camera/rgb/camera_info in" in r.stdout
    a = (out / "folder" / "CameraTrajectory.txt").read_bytes()
    b = (out / "bag" / "CameraTrajectory.txt").read_bytes()
    assert len(a.splitlines()) == frames + 1
    assert a == b
    sa = json.loads((out / "folder" / "summary.json").read_text())
    sb = json.loads((out / "bag" / "summary.json").read_text())
    assert sb["ate"]["rmse"] == sa["ate"]["rmse"]
    return sb
