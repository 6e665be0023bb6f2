#!/usr/bin/env bash
# Sets up a fresh Debian bookworm machine, builds lrd-slam and runs the main job on the built-in
# default: it renders the default synthetic dynamic sequence (walking_xyz, seed 1, realism profile
# `tum`), runs SLAM on it with the dense map and prints ATE/RPE against its ground truth (with
# plots). With the shipped segmentation model (models/fnet-lite.onnx) it runs the full LRD-SLAM (C)
# mode; without it, the model-free `geometric` mode (the multi-view geometry check alone).
# Usage: scripts/run-default.sh [OUT_DIR]   (default: out/default)
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/default}
# Only what this job needs: the toolchain and the libraries the CLI links (no ROS, DDS, Python,
# Slurm, browser or training packages; scripts/run-tests.sh and docs/install.md add those).
bash scripts/install-deps.sh --main
# The charting libraries the HTML report inlines (npm package uplot and three into data/web/), when
# npm is there; without them the run writes everything but report.html.
if command -v npm >/dev/null 2>&1; then
  bash scripts/fetch-web-assets.sh || echo "warning: scripts/fetch-web-assets.sh failed; no HTML report" >&2
fi
# The CLI alone, in unity batches (about eight files per compile): the tests, benchmarks and
# nodes are built by scripts/run-tests.sh or `cmake --build --preset release`.
cmake --preset release -DLRD_UNITY_BUILD=ON
cmake --build --preset release -j "$(nproc)" --target lrdslam_cli
BIN=build/release/bin/lrdslam
# The realism profile of a real Kinect in TUM's office (docs/synthetic-benchmark.md):
# blur, rolling shutter, noise, distortion and a slightly wrong calibration, TUM's camera motion.
SEQ="$OUT/walking_xyz_tum"
if [ ! -f "$SEQ/sequence.json" ]; then
  "$BIN" synth --preset walking_xyz --seed 1 --realism tum --out "$SEQ"
fi
if [ -f models/fnet-lite.onnx ]; then MODE=(--mode full --segmenter fnet); else MODE=(--mode geometric); fi
MODE+=(--dense)  # background repair and the dense map (dense_map.ply/.png), the occupancy map (occupancy.bt, occupancy_2d.*)
if [ -f data/web/uPlot.iife.min.js ] && [ -f data/web/three.min.js ]; then
  MODE+=(--report)  # OUT/run/report.html
else
  echo "note: no HTML report (its charting libraries need npm: sudo apt install npm && scripts/fetch-web-assets.sh)" >&2
fi
"$BIN" run --sequence "$SEQ" --out "$OUT/run" "${MODE[@]}"
"$BIN" eval "$SEQ/groundtruth.txt" "$OUT/run/CameraTrajectory.txt" --json "$OUT/eval.json" --plot "$OUT/plots"
echo "Sequence: $SEQ   trajectory: $OUT/run/CameraTrajectory.txt   dense map: $OUT/run/dense_map.ply   occupancy grid: $OUT/run/occupancy_2d.png   evaluation: $OUT/eval.json   plots: $OUT/plots   report: $OUT/run/report.html"
