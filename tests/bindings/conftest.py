"""The Python module's tests: `lrdslam` from a release build (ctest sets PYTHONPATH and
LRDSLAM_BIN to the same build's package and CLI, so both run the same library)."""
import os
import subprocess

import pytest

BIN = os.environ.get("LRDSLAM_BIN", "build/release/bin/lrdslam")

try:
    import lrdslam  # noqa: F401
except ImportError as e:  # pragma: no cover - a build without pybind11
    if os.environ.get("CI"):
        raise
    pytest.skip(f"the lrdslam module is not built ({e}); scripts/install-deps.sh installs pybind11",
                allow_module_level=True)


def cli(*args):
    r = subprocess.run([BIN, *map(str, args)], capture_output=True, text=True)
    assert r.returncode == 0, f"lrdslam {' '.join(map(str, args))} failed:\n{r.stdout}\n{r.stderr}"
    return r


@pytest.fixture(scope="session")
def walking(tmp_path_factory):
    """A 60-frame walking_xyz prefix written by `lrdslam synth` (TUM layout, with ground truth)."""
    folder = tmp_path_factory.mktemp("seq") / "walking_xyz"
    cli("synth", "--preset", "walking_xyz", "--frames", 60, "--out", folder)
    return folder
