#!/usr/bin/env bash
# Prints the SHA-256 of every output a `--deterministic` run writes (trajectories, dense map,
# occupancy grid, saved map) for the walking and loop presets in `full` mode. Run it before and after
# a change that must not move a single output byte (a refactor) and diff the two listings; the
# listing recorded with such a change lives in bench/results/architecture.md.
# Usage: bench/deterministic-outputs.sh [BIN] [OUT_DIR]   (default: build/release/bin/lrdslam, /tmp/lrd-deterministic)
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${1:-build/release/bin/lrdslam}
OUT=${2:-/tmp/lrd-deterministic}
PRESETS=(walking_xyz walking_static walking_rpy walking_halfsphere walking_loop static_loop)
for preset in "${PRESETS[@]}"; do
  dir="$OUT/$preset"
  rm -rf "$dir"
  "$BIN" run --synth "$preset" --deterministic --mode full --segmenter fnet --dense \
    --save-map "$dir/map.lrdmap" --out "$dir" --quiet >/dev/null
  for file in CameraTrajectory.txt KeyFrameTrajectory.txt dense_map.ply occupancy_2d.pgm map.lrdmap; do
    if [ -f "$dir/$file" ]; then
      echo "$preset/$file $(sha256sum < "$dir/$file" | cut -c1-16)"
    fi
  done
done
