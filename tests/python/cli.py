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
