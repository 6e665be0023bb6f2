"""Running the lrdslam CLI from the tests (ctest sets LRDSLAM_BIN to the build's binary)."""
import json
import os
import re
import subprocess

BIN = os.environ.get("LRDSLAM_BIN", "build/release/bin/lrdslam")


def lrdslam(*args, check=True):
    """Runs `lrdslam ARGS`; with check, a non-zero exit fails the test with its output."""
    r = subprocess.run([BIN, *map(str, args)], capture_output=True, text=True)
    if check and r.returncode != 0:
        raise AssertionError(f"lrdslam {' '.join(map(str, args))} failed:\n{r.stdout}\n{r.stderr}")
    return r


def page_data(html):
    """The data a report page (lrdslam report) carries in its #report-data script."""
    m = re.search(r'<script type="application/json" id="report-data">(.*?)</script>', html, re.S)
    assert m, "no report data in the page"
    return json.loads(m.group(1))
