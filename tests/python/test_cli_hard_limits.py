"""Hard limits: `lrdslam run` with its output folder on a full disk, or under a memory limit
(ulimit -v), ends with one line on stderr and exit 1 — never a crash, a hang or a half-written file,
and the previous run's outputs stay as they were. A file-size limit (RLIMIT_FSIZE, its signal
ignored: writes past it fail with EFBIG) stands in for a full disk where no tmpfs can be mounted;
as root, a real full tmpfs is tested too."""
import os
import resource
import shutil
import signal
import subprocess

import pytest

from cli import BIN, synth_input

FRAMES = 40  # enough for an RPE pair, so the run prints no warning


@pytest.fixture(scope="module")
def sequence(tmp_path_factory):
    d = tmp_path_factory.mktemp("seq") / "walking_xyz"
    synth_input("--preset", "walking_xyz", "--frames", FRAMES, "--out", d)
    return d


@pytest.fixture(scope="module")
def good_run(sequence, tmp_path_factory):
    """A finished run's output folder, with the dense and occupancy maps."""
    out = tmp_path_factory.mktemp("good") / "out"
    r = run(sequence, out, "--occupancy")
    assert r.returncode == 0, r.stderr
    return out


def run(sequence, out, *extra, preexec_fn=None):
    return subprocess.run([BIN, "run", "--sequence", str(sequence), "--out", str(out), "--quiet", *extra],
                          capture_output=True, text=True, preexec_fn=preexec_fn, timeout=180)


def file_size_limit(limit):
    def set_limit():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
    return set_limit


def snapshot(folder):
    """Each file's bytes and inode (a file renamed over it has another)."""
    return {p.name: (p.read_bytes(), p.stat().st_ino) for p in sorted(folder.iterdir()) if p.is_file()}


def one_error_line(r):
    assert r.returncode == 1, f"exit {r.returncode}:\n{r.stdout}\n{r.stderr}"
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith("error: "), lines[0]
    return lines[0]


@pytest.mark.parametrize(
    "limit, failing, extra",
    [
        (512, "CameraTrajectory.txt", []),  # the first file a run writes
        (200_000, "dense_map.ply", ["--occupancy"]),  # the trajectories fit, the dense map does not
    ],
)
def test_a_full_disk_is_one_line_naming_the_file_and_keeps_the_previous_file(sequence, good_run, tmp_path,
                                                                               limit, failing, extra):
    out = tmp_path / "out"
    shutil.copytree(good_run, out)
    assert (out / failing).stat().st_size > limit
    before = snapshot(out)
    r = run(sequence, out, *extra, preexec_fn=file_size_limit(limit))
    line = one_error_line(r)
    assert line == f"error: {out / failing}: cannot write (File too large)", line
    after = snapshot(out)
    assert after.keys() == before.keys(), "a temporary was left behind, or a file removed"
    assert after[failing] == before[failing]
    assert after["summary.json"] == before["summary.json"]  # written last, so never reached


def test_a_real_full_disk_is_one_line_naming_the_file(sequence, good_run, tmp_path):
    disk = tmp_path / "disk"
    disk.mkdir()
    if os.geteuid() != 0 or subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", str(disk)],
                                           capture_output=True).returncode != 0:
        pytest.skip("cannot mount a tmpfs here (needs root)")
    try:
        out = disk / "out"
        out.mkdir()
        for name in ("CameraTrajectory.txt", "summary.json"):
            shutil.copy(good_run / name, out / name)
        with open(disk / "filler", "wb", buffering=0) as f:  # the rest of the disk
            try:
                while True:
                    f.write(b"\0" * 4096)
            except OSError:
                pass
        before = snapshot(out)
        line = one_error_line(run(sequence, out))
        assert line == f"error: {out / 'CameraTrajectory.txt'}: cannot write (No space left on device)", line
        assert snapshot(out) == before
    finally:
        subprocess.run(["umount", str(disk)], check=True)


# Address-space limits (ulimit -v) from a little above what the program needs to start to well below
# what the run needs. Where a limit is met depends on the machine's cores (threads' stacks, malloc's
# per-thread arenas) and on timing: starting a thread, decoding a frame, in a worker — or, on a
# machine that needs less, nowhere. Whatever happens: exit 0, or exit 1 with one error line.
MEMORY_LIMITS_MB = [288, 384, 480]
# libpng, inside OpenCV's decoder, reports its own allocation failures on stderr before OpenCV
# returns; nothing of ours can silence it.
THIRD_PARTY = ("libpng ",)


def address_space_limit(limit):
    def set_limit():
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    return set_limit


def sanitized():
    """Whether the binary is a sanitizer build: its runtime reserves terabytes of address space for
    its shadow memory, so any ulimit -v stops it before main."""
    with open(BIN, "rb") as f:
        return any(name in f.read() for name in (b"libasan.so", b"libtsan.so", b"__asan_init"))


@pytest.mark.parametrize("deterministic", [False, True])
def test_a_memory_limit_ends_the_run_with_one_line_and_exit_1(sequence, tmp_path, deterministic):
    if sanitized():
        pytest.skip("a sanitizer build cannot run under an address-space limit")
    stopped = []
    for mb in MEMORY_LIMITS_MB:
        extra = ["--dense"] + (["--deterministic"] if deterministic else [])
        r = run(sequence, tmp_path / f"out{mb}", *extra, preexec_fn=address_space_limit(mb << 20))
        if r.returncode == 127 and "error while loading shared libraries" in r.stderr:
            continue  # too little for the dynamic loader, before any of our code runs
        assert r.returncode in (0, 1), f"{mb} MB: exit {r.returncode} (a signal?):\n{r.stderr}"
        if r.returncode == 0:
            continue
        lines = [line for line in r.stderr.strip().splitlines() if not line.startswith(THIRD_PARTY)]
        assert len(lines) == 1 and lines[0].startswith("error: "), f"{mb} MB:\n{r.stderr}"
        assert "out of memory" in lines[0] or "Resource temporarily unavailable" in lines[0], lines[0]
        stopped.append(mb)
    assert stopped, f"none of {MEMORY_LIMITS_MB} MB stopped the run: too generous for this machine"
