"""Running the lrdslam CLI from the tests (ctest sets LRDSLAM_BIN to the build's binary)."""
import os
import subprocess

BIN = os.environ.get("LRDSLAM_BIN", "build/release/bin/lrdslam")


def lrdslam(*args, check=True):
    """Runs `lrdslam ARGS`; with check, a non-zero exit fails the test with its output."""
    r = subprocess.run([BIN, *map(str, args)], capture_output=True, text=True)
    if check and r.returncode != 0:
        raise AssertionError(f"lrdslam {' '.join(map(str, args))} failed:\n{r.stdout}\n{r.stderr}")
    return r
