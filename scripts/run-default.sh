#!/usr/bin/env bash
# Sets up a fresh Debian bookworm machine, builds lrd-slam and runs the main job on the built-in
# default: it renders the default synthetic dynamic sequence (walking_xyz, seed 1) and evaluates
# against its ground truth. Until the SLAM core lands, the trajectory evaluated is the
# "camera assumed still" baseline — the score any SLAM run must beat.
# Usage: scripts/run-default.sh [OUT_DIR]   (default: out/default)
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/default}
bash scripts/install-deps.sh
cmake --preset release
cmake --build --preset release -j "$(nproc)"
BIN=build/release/bin/lrdslam
SEQ="$OUT/walking_xyz"
if [ ! -f "$SEQ/sequence.json" ]; then
  "$BIN" synth --preset walking_xyz --seed 1 --out "$SEQ"
fi
# Baseline: every frame at the first ground-truth pose.
awk '!/^#/ && NF == 8 { if (!p) { p = $2" "$3" "$4" "$5" "$6" "$7" "$8 } print $1, p }' \
  "$SEQ/groundtruth.txt" > "$OUT/still_camera_baseline.txt"
"$BIN" eval "$SEQ/groundtruth.txt" "$OUT/still_camera_baseline.txt" --json "$OUT/eval.json" --plot "$OUT/plots"
echo "Sequence: $SEQ   evaluation: $OUT/eval.json   plots: $OUT/plots"
