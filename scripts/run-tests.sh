#!/usr/bin/env bash
# Sets up a fresh Debian bookworm machine and runs every test (GoogleTest through ctest, and the
# Python tests, which ctest runs with /usr/bin/python3 -m pytest) under ASan + UBSan. It also
# builds the release preset, so the benchmarks (which the asan preset leaves out) compile cleanly.
# Usage: scripts/run-tests.sh            (what CI runs)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset asan
cmake --build --preset asan -j "$(nproc)"
cmake --preset release
cmake --build --preset release -j "$(nproc)"
ctest --preset asan
bash scripts/check-install.sh
