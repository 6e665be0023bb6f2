"""`lrdslam --version`: the version CMakeLists.txt declares, which CHANGELOG.md's newest entry
names, and the git commit the binary was built from."""
import re
import subprocess
from pathlib import Path

from cli import lrdslam

ROOT = Path(__file__).resolve().parents[2]


def declared_version():
    m = re.search(r"project\(lrdslam VERSION (\d+\.\d+\.\d+)", (ROOT / "CMakeLists.txt").read_text())
    assert m, "CMakeLists.txt declares no project VERSION"
    return m.group(1)


def test_version_prints_the_declared_version_and_the_commit():
    out = lrdslam("--version").stdout.strip()
    m = re.fullmatch(r"lrdslam (\d+\.\d+\.\d+) \(([0-9a-f]{7,40})(-dirty)?\)", out)
    assert m, f"unexpected --version output: {out!r}"
    assert m.group(1) == declared_version()
    # The commit is one of this repository's (the binary may predate the newest commit).
    known = subprocess.run(["git", "-C", str(ROOT), "cat-file", "-e", m.group(2) + "^{commit}"])
    assert known.returncode == 0, f"--version names commit {m.group(2)}, unknown to this repository"


def test_changelog_names_the_version_first():
    entries = re.findall(r"^## (\d+\.\d+\.\d+) — (\d{4}-\d{2}-\d{2})$", (ROOT / "CHANGELOG.md").read_text(), re.M)
    assert entries, "CHANGELOG.md has no '## X.Y.Z — DATE' entry"
    assert entries[0][0] == declared_version()
    versions = [tuple(map(int, v.split("."))) for v, _ in entries]
    assert versions == sorted(versions, reverse=True), "CHANGELOG.md lists versions newest first"


def test_minimal_example_asks_for_a_version_the_package_accepts():
    # The installed package config accepts the same major.minor (SameMinorVersion in src/CMakeLists.txt:
    # before 1.0 a minor release may change the API), so the example must ask for the current minor.
    assert "COMPATIBILITY SameMinorVersion" in (ROOT / "src" / "CMakeLists.txt").read_text()
    m = re.search(r"find_package\(lrdslam (\d+)\.(\d+)", (ROOT / "examples" / "minimal" / "CMakeLists.txt").read_text())
    assert m, "examples/minimal/CMakeLists.txt asks for no lrdslam version"
    major, minor, _ = declared_version().split(".")
    assert (m.group(1), m.group(2)) == (major, minor), f"example asks for {m.group(1)}.{m.group(2)}, package is {declared_version()}"
