"""A corpus of bad inputs, generated at test time from one valid synthetic sequence.

Each case copies what it needs of a 12-frame `walking_xyz` render (images as symbolic links, so a
case costs a few kilobytes), applies ONE corruption and runs `lrdslam run` on it (under ctest the
binary is the AddressSanitizer + UBSan build). The contract for every case:

  * a non-zero exit status, and not a signal;
  * stderr is exactly one line, `error: ...`, that names the offending file (its basename is
    enough) - spdlog lines, if any reach stderr, are not counted;
  * no sanitizer report, no `terminate called`, no segmentation fault, no hang.

The families: PNG images (truncated, bit-flipped, garbage, wrong bit depth / channel count,
colour/depth size mismatch, a header claiming 100000 x 100000 pixels, a real 20000 x 20000
image), the list files (rgb.txt, depth.txt, associations.txt, groundtruth.txt: garbage, wrong
field counts, bad numbers, duplicate and unsorted lines, empty, binary), ORB-SLAM settings and
lrd-slam config files (NaN, negative, zero and huge values, syntax errors, unknown and duplicate
keys), vocabularies and ONNX models (empty, truncated, bit-flipped, wrong magic), ground-truth
mask folders, and folders that are empty, missing or files.

"Unreadable" files: the tests run as root in CI, and `chmod 000` does not stop root from reading
a file, so unreadability is made with things no user can read as a regular file: a directory
where the file should be, a dangling symbolic link and a symbolic link that points to itself
(ELOOP). FIFOs are not used: opening one for reading blocks until a writer appears.

Cases that show a known lrdslam bug are marked xfail(strict=True) with the reason; when the bug
is fixed the case passes and strict xfail makes the suite fail, so the marker gets removed.
The module prints "bad-input corpus: N cases, P passed, X xfailed (known bugs)" at the end.

The cases live in bad_inputs/ by kind (images and masks, list files and folders, settings and
config, vocabulary and model); this file runs them.
"""
import contextlib
import os
import re
import subprocess

import pytest

from bad_inputs import CASES, Ctx, huge_grey_png
from cli import BIN, synth_input

FRAMES = 12
TIMEOUT_S = 120  # a hang is a failure, not a stuck suite

# Anything here on stdout or stderr is a crash report, whatever the exit status says.
CRASH_MARKS = ("AddressSanitizer", "LeakSanitizer", "UndefinedBehaviorSanitizer", "runtime error:",
               "ThreadSanitizer", "terminate called", "Segmentation fault", "core dumped", "Aborted")
# spdlog's default pattern: "[2026-12-02 02:28:21.393] [warning] ..."
SPDLOG_LINE = re.compile(r"^\[\d{4}-\d\d-\d\d [\d:.]+\] \[\w+\]")

# ---------------------------------------------------------------------------------------------
# Fixtures, the check, the summary

RESULTS: dict = {}


@pytest.fixture(scope="session")
def base_sequence(tmp_path_factory):
    d = tmp_path_factory.mktemp("bad_input_base") / "walking_xyz"
    synth_input("--preset", "walking_xyz", "--frames", FRAMES, "--out", d)
    frames = []
    for line in (d / "associations.txt").read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            f = line.split()
            frames.append((f[1], f[3]))
    assert len(frames) == FRAMES
    return d, frames


@pytest.fixture(scope="session")
def big_png(tmp_path_factory):
    """20000 x 20000 PNG bytes, made once and only when a case asks for it."""
    cache = {}

    def get():
        if "png" not in cache:
            cache["png"] = huge_grey_png(20000, 20000)
        return cache["png"]

    return get


@pytest.fixture(scope="module", autouse=True)
def corpus_summary(request):
    yield
    if not RESULTS:
        return
    passed = sum(1 for ok, _ in RESULTS.values() if ok)
    xfailed = sum(1 for ok, bug in RESULTS.values() if not ok and bug)
    failed = len(RESULTS) - passed - xfailed
    line = f"bad-input corpus: {len(RESULTS)} cases, {passed} passed, {xfailed} xfailed (known bugs)"
    if failed:
        line += f", {failed} FAILED"
    # Past pytest's output capture (which would swallow it in a passing run), like capsys.disabled().
    capture = request.config.pluginmanager.get_plugin("capturemanager")
    reporter = request.config.pluginmanager.get_plugin("terminalreporter")
    with capture.global_and_fixture_disabled() if capture is not None else contextlib.nullcontext():
        if reporter is not None:
            reporter.write_line("")
            reporter.write_line(line)
        else:
            print(line, flush=True)


def problems_with(r, expect: str):
    """What breaks the contract, as a list of sentences (empty: the case passed)."""
    out = []
    if r.returncode < 0:
        out.append(f"killed by signal {-r.returncode}")
    elif r.returncode == 0:
        out.append("exit status 0")
    for mark in CRASH_MARKS:
        if mark in r.stderr or mark in r.stdout:
            out.append(f"'{mark}' in the output")
    lines = [l for l in r.stderr.splitlines() if l.strip() and not SPDLOG_LINE.match(l)]
    if len(lines) != 1:
        out.append(f"{len(lines)} lines on stderr, expected one")
    elif not lines[0].startswith("error: "):
        out.append("the stderr line does not start with 'error: '")
    elif expect not in lines[0]:
        out.append(f"the error does not name '{expect}'")
    return out


def params():
    for c in CASES:
        marks = [pytest.mark.xfail(strict=True, reason=c.bug)] if c.bug else []
        yield pytest.param(c, id=c.id, marks=marks)


def test_corpus_is_large_enough():
    assert len(CASES) >= 100
    assert len({c.id for c in CASES}) == len(CASES), "duplicate case ids"


@pytest.mark.parametrize("c", params())
def test_bad_input(c, base_sequence, big_png, tmp_path):
    base, frames = base_sequence
    ok = False
    try:
        ctx = Ctx(base, tmp_path, frames, big_png)
        extra, expect = c.prepare(ctx)
        extra = [str(a) for a in extra]
        cmd = [BIN, "run", "--sequence", str(ctx.sequence), "--quiet", "--no-loop-closing",
               "--max-frames", str(ctx.max_frames)]
        if "--out" not in extra:
            cmd += ["--out", str(tmp_path / "out")]
        cmd += extra
        env = dict(os.environ)
        # what the asan test preset sets: any report is fatal
        env.setdefault("ASAN_OPTIONS", "detect_leaks=1:abort_on_error=1")
        env.setdefault("UBSAN_OPTIONS", "print_stacktrace=1:halt_on_error=1")
        try:
            r = subprocess.run(cmd, capture_output=True, text=True, errors="replace", timeout=TIMEOUT_S, env=env)
        except subprocess.TimeoutExpired:
            pytest.fail(f"hung for {TIMEOUT_S} s: {' '.join(cmd)}")
        problems = problems_with(r, expect)
        assert not problems, (f"{'; '.join(problems)}\n$ {' '.join(cmd)}\nexit {r.returncode}\n"
                              f"--- stderr ---\n{r.stderr[-4000:]}\n--- stdout ---\n{r.stdout[-2000:]}")
        ok = True
    finally:
        RESULTS[c.id] = (ok, c.bug)
