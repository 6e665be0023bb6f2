#!/usr/bin/env bash
# Installs the release build into a temporary prefix and builds examples/minimal against it with
# find_package(lrdslam), then runs it on a short synthetic sequence: the library is usable as a
# package, headers and CMake config included. Needs build/release (scripts/run-tests.sh builds it).
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake --install build/release --prefix "$tmp/prefix" >/dev/null
cmake -S examples/minimal -B "$tmp/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$tmp/prefix" >/dev/null
cmake --build "$tmp/build" >/dev/null
build/release/bin/lrdslam synth --preset static_xyz --frames 30 --out "$tmp/seq" >/dev/null
"$tmp/build/minimal_slam" "$tmp/seq" "$tmp/trajectory.txt"
test "$(grep -vc '^#' "$tmp/trajectory.txt")" -ge 25
echo "check-install: OK (installed package builds and tracks)"
