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
# The Python module, where this build has one: installed for /usr/bin/python3, it tracks the same
# sequence from the prefix (not the build tree).
if compgen -G "build/release/python/lrdslam/_core*.so" >/dev/null; then
  site=$(find "$tmp/prefix" -path '*dist-packages/lrdslam/__init__.py' -printf '%h\n' | head -n1)
  [ -n "$site" ] || { echo "check-install: cmake --install put no lrdslam package under $tmp/prefix" >&2; exit 1; }
  PYTHONPATH=$(dirname "$site") /usr/bin/python3 - "$tmp/seq" "$site" <<'PY'
import sys
import lrdslam
assert lrdslam.__file__.startswith(sys.argv[2]), lrdslam.__file__
seq = lrdslam.io.read_sequence(sys.argv[1])
with lrdslam.System(sequence=seq, mode="static") as slam:
    states = [slam.track_rgbd(f.rgb, f.depth, f.timestamp).state for f in seq]
assert states.count("ok") >= 25, states
PY
  echo "check-install: OK (installed Python module imports and tracks)"
fi
