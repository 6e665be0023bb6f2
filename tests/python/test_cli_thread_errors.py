"""An exception in any worker thread ends `lrdslam run` with a one-line error naming the thread and
exit 1: never std::terminate, never a hang. The failures are injected by the test hook
LRDSLAM_FAIL_AT (src/lrd/util/fault_injection.h)."""
import os
import subprocess

import pytest

from cli import BIN, lrdslam, synth_input

FRAMES = 60


@pytest.fixture(scope="module")
def sequence(tmp_path_factory):
    d = tmp_path_factory.mktemp("seq") / "walking_xyz"
    synth_input("--preset", "walking_xyz", "--frames", FRAMES, "--out", d)
    return d


@pytest.mark.parametrize(
    "point, thread, extra",
    [
        ("local_mapping", "local mapping thread", []),
        ("loop_closing", "loop closing thread", []),
        ("segmentation", "segmentation thread", ["--mode", "full", "--segmenter", "gt-masks"]),
        ("dense", "dense mapping thread", ["--dense"]),
        ("prefetcher", "prefetcher", []),
    ],
)
@pytest.mark.parametrize("deterministic", [False, True])
def test_a_failing_thread_ends_the_run_with_one_line_naming_it(sequence, tmp_path, point, thread, extra,
                                                              deterministic):
    if point == "prefetcher" and deterministic:
        pytest.skip("the prefetcher runs the same in both modes")
    args = [BIN, "run", "--sequence", str(sequence), "--out", str(tmp_path / "o"), "--quiet", *extra]
    if deterministic:
        args.append("--deterministic")
    env = dict(os.environ, LRDSLAM_FAIL_AT=point)
    r = subprocess.run(args, capture_output=True, text=True, env=env, timeout=300)
    assert r.returncode == 1, r.stdout + r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith("error: ") and thread in lines[0], lines[0]
    assert f"injected failure at {point}" in lines[0]


def test_without_the_hook_the_same_run_succeeds(sequence, tmp_path):
    r = lrdslam("run", "--sequence", sequence, "--out", tmp_path / "o", "--quiet", "--dense", "--mode", "full",
                "--segmenter", "gt-masks")
    assert "error" not in r.stderr.lower()
