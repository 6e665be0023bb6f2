#!/usr/bin/env bash
# Sets up a fresh Debian bookworm machine and runs every test (GoogleTest through ctest, and the
# Python tests, which ctest runs with /usr/bin/python3 -m pytest) under ASan + UBSan, then the
# threaded tests under ThreadSanitizer (the tsan preset: System runs, segmentation, dense mapping,
# loop closing with global BA, the prefetcher, the work queue, the publisher). It also builds the
# release preset, so the benchmarks (which the asan preset leaves out) compile cleanly.
# Usage: scripts/run-tests.sh            (what CI runs)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
# The MediaPipe person models for real data (npm package, converted by tools/tflite2onnx into
# data/models/). Without the npm registry their tests skip and their presets say how to get them.
bash scripts/fetch-models.sh || echo "warning: scripts/fetch-models.sh failed; the selfie presets are unavailable" >&2
# The charting library the HTML report inlines (npm package uplot into data/web/); its tests need it.
bash scripts/fetch-web-assets.sh
# Foxglove's MCAP and ROS 2 CDR packages (npm, into data/npm-ros2/): the ROS 2 bag cross-check
# (tests/ros2/); without them its tests skip.
bash scripts/fetch-ros2-test-peers.sh
cmake --preset asan
cmake --build --preset asan -j "$(nproc)"
# Unity batches (LRD_UNITY_BUILD, as the asan and tsan presets have): minutes less on two cores. It
# stays in build/release's cache: `cmake --preset release -DLRD_UNITY_BUILD=OFF` for one-file rebuilds.
cmake --preset release -DLRD_UNITY_BUILD=ON
# Every program but the tests (target lrd_programs): the asan build above runs those. Built before
# the tests run: the Python tests render their input sequences with it (tests/python/cli.py).
cmake --build --preset release -j "$(nproc)" --target lrd_programs
ctest --preset asan
cmake --preset tsan
cmake --build --preset tsan -j "$(nproc)"
ctest --preset tsan
bash scripts/check-install.sh
