#!/usr/bin/env python3
"""Fails on words about how the project was developed, in any tracked text file.

Code, comments, docs, tests and results speak of the product: a comment says why the code is as
it is (the paper's section, a measurement and its results file), a results file says when and how
a figure was measured. References to work sessions, to a tracker's issue numbers or to earlier builds
mean nothing to a user or a contributor, so this check (a ctest test, `dev_words`) names each such
line.

Usage: scripts/check-dev-words.py [ROOT]    (default: the repository this script lives in)
"""
import re
import subprocess
import sys
from pathlib import Path

# Each pattern is a way the development process shows through. Case-insensitive.
PATTERNS = [
    r"\bissues? ?#?\d+",                  # a tracker issue by number
    r"\b(work )?sessions? \d+",           # a work session by number
    r"\b(this|next|last|previous|earlier|prior|later) (work )?session\b",
    r"\bthe\s+build\s+before\b",
    r"\bbefore this change\b",
    r"\b(this|last|previous|next) round\b",
    r"\bstop \d+\b",                      # the tracker's stops
    r"\b(reliability|architecture|ros|ros 2|scale|map-file|dense) issue\b",  # an issue by its theme
    r"\bthe issue'?s\b",                  # a bar named by whose it was
    r"\bissue( bar|:)",
]

# Legitimate uses, allowed by name: a map file's sessions are a feature (a run that continues a
# saved map is its second session; `lrdslam synth --session N` renders one from another standpoint).
ALLOWED = [
    r"--session\b",
    r"\bsession=",
    r"map[- ]file sessions?\b",
    r"\bsessions? [123] (and|or|to|\.\.) [123]\b",
    r"\bsession [123] (of|in|is|tracked|continues|loads|renders|saves|sees|made)\b",
]

# Files that are not text we write: models, images, vendored data, and this check itself.
SKIPPED_SUFFIXES = {".png", ".jpg", ".svg", ".onnx", ".pt", ".bin", ".ply", ".bt", ".bag", ".db3",
                    ".mcap", ".pgm", ".gz", ".zst", ".lz4", ".tflite", ".ico"}
SKIPPED_PREFIXES = ("vocab/", "models/", "tests/data/fuzz/", "bench/fuzz/corpus/")


def tracked_files(root: Path):
    out = subprocess.run(["git", "-C", str(root), "ls-files", "-z"], check=True, capture_output=True)
    for name in out.stdout.decode().split("\0"):
        if not name or name.startswith(SKIPPED_PREFIXES) or Path(name).suffix in SKIPPED_SUFFIXES:
            continue
        if name == "scripts/check-dev-words.py":
            continue
        yield name


def main() -> int:
    root = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parent.parent
    found = re.compile("|".join(PATTERNS), re.IGNORECASE)
    allowed = re.compile("|".join(ALLOWED), re.IGNORECASE)
    hits = 0
    for name in tracked_files(root):
        path = root / name
        try:
            text = path.read_text(encoding="utf-8")
        except (UnicodeDecodeError, FileNotFoundError, IsADirectoryError):
            continue
        for number, line in enumerate(text.splitlines(), 1):
            match = found.search(line)
            if match and not allowed.search(line):
                print(f"{name}:{number}: '{match.group(0)}': {line.strip()[:120]}")
                hits += 1
    if hits:
        print(f"check-dev-words: {hits} line(s) speak of how the project was developed, not of the product")
        return 1
    print("check-dev-words: clean")
    return 0


if __name__ == "__main__":
    sys.exit(main())
