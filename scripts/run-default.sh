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
bash scripts/install-deps.sh
# The MediaPipe person models for real data (npm package, converted by tools/tflite2onnx into
# data/models/). Without the npm registry their tests skip and their presets say how to get them.
bash scripts/fetch-models.sh || echo "warning: scripts/fetch-models.sh failed; the selfie presets are unavailable" >&2
# The charting library the HTML report inlines (npm package uplot into data/web/).
bash scripts/fetch-web-assets.sh || echo "warning: scripts/fetch-web-assets.sh failed; no HTML report" >&2
cmake --preset release
cmake --build --preset release -j "$(nproc)"
BIN=build/release/bin/lrdslam
# The realism profile of a real Kinect in TUM's office (issue 21, docs/synthetic-benchmark.md):
# blur, rolling shutter, noise, distortion and a slightly wrong calibration, TUM's camera motion.
SEQ="$OUT/walking_xyz_tum"
if [ ! -f "$SEQ/sequence.json" ]; then
  "$BIN" synth --preset walking_xyz --seed 1 --realism tum --out "$SEQ"
fi
if [ -f models/fnet-lite.onnx ]; then MODE=(--mode full --segmenter fnet); else MODE=(--mode geometric); fi
MODE+=(--dense)  # background repair and the dense map (dense_map.ply/.png), the occupancy map (occupancy.bt, occupancy_2d.*)
if [ -f data/web/uPlot.iife.min.js ] && [ -f data/web/three.min.js ]; then MODE+=(--report); fi  # OUT/run/report.html
"$BIN" run --sequence "$SEQ" --out "$OUT/run" "${MODE[@]}"
"$BIN" eval "$SEQ/groundtruth.txt" "$OUT/run/CameraTrajectory.txt" --json "$OUT/eval.json" --plot "$OUT/plots"
echo "Sequence: $SEQ   trajectory: $OUT/run/CameraTrajectory.txt   dense map: $OUT/run/dense_map.ply   occupancy grid: $OUT/run/occupancy_2d.png   evaluation: $OUT/eval.json   plots: $OUT/plots   report: $OUT/run/report.html"
