#!/usr/bin/env bash
# Fuzzes lrd-slam's readers of outside data with libFuzzer (clang-14 from Debian, with ASan and
# UBSan): builds the fuzz preset, makes the seeds (fuzz_make_seeds: the project's own writers; a
# map file from a short `lrdslam run --save-map`), then runs each harness for N seconds, one a
# core, with its dictionary (bench/fuzz/dict/HARNESS.dict) where it has one. The
# corpus grows in out/fuzz/corpus/HARNESS; a crash leaves out/fuzz/crash/HARNESS/crash-* (make it a
# regression input in tests/fuzz/corpus/HARNESS/ once fixed). Prints per harness the executions,
# coverage features and crashes (the figures of bench/results/fuzz.md).
#   bench/fuzz/run.sh [--seconds N] [HARNESS...]     (default: 600 s, every harness)
set -euo pipefail
cd "$(dirname "$0")/../.."

SECONDS_EACH=600
HARNESSES=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) SECONDS_EACH=$2; shift 2 ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) HARNESSES+=("$1"); shift ;;
  esac
done
ALL=(tum_lists orbslam_settings yaml_config map_file vocabulary ply rosbag2 cdr_messages image_messages rosbag1)

command -v clang++-14 >/dev/null || { echo "run.sh: clang++-14 not found (apt install clang-14)" >&2; exit 2; }
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$(nproc)"
# rosbag1 exists where ROS 1 is installed (Debian's rosbag_storage).
if [ ${#HARNESSES[@]} -eq 0 ]; then
  for h in "${ALL[@]}"; do [ -x "build/fuzz/bin/fuzz/fuzz_$h" ] && HARNESSES+=("$h"); done
fi
OUT=out/fuzz
mkdir -p "$OUT/seeds" "$OUT/corpus" "$OUT/crash" "$OUT/log"
build/fuzz/bin/fuzz/fuzz_make_seeds "$OUT/seeds" config >/dev/null
if [ ! -f "$OUT/seeds/map_file/seed_run" ] && [ -x build/release/bin/lrdslam ]; then
  # A map file from a short run, without its checksum (the harness appends one).
  build/release/bin/lrdslam run --synth static_xyz --frames 12 --save-map "$OUT/run.lrdmap" --out "$OUT/run" \
    --quiet >/dev/null
  mkdir -p "$OUT/seeds/map_file"
  head -c -8 "$OUT/run.lrdmap" >"$OUT/seeds/map_file/seed_run"
fi

run_one() {
  local h=$1 dict=()
  mkdir -p "$OUT/corpus/$h" "$OUT/crash/$h"
  [ -f "bench/fuzz/dict/$h.dict" ] && dict=(-dict="bench/fuzz/dict/$h.dict")
  local seeds=("$OUT/seeds/$h")
  [ -d "tests/fuzz/corpus/$h" ] && seeds+=("tests/fuzz/corpus/$h")
  # -rss_limit_mb: a reader asked to allocate gigabytes by a header is a finding too.
  build/fuzz/bin/fuzz/fuzz_"$h" "$OUT/corpus/$h" "${seeds[@]}" "${dict[@]}" -max_total_time="$SECONDS_EACH" \
    -max_len=1048576 -rss_limit_mb=2048 -timeout=20 -print_final_stats=1 -artifact_prefix="$OUT/crash/$h/" \
    >"$OUT/log/$h.log" 2>&1 || true
}
export -f run_one
export OUT SECONDS_EACH

# One harness a core; the next starts when one ends (a crash ends a harness early).
printf '%s\n' "${HARNESSES[@]}" | xargs -P "$(nproc)" -I{} bash -c 'run_one {}'

printf '%-18s %12s %10s %8s %8s\n' harness executions features corpus crashes
for h in "${HARNESSES[@]}"; do
  log="$OUT/log/$h.log"
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  features=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || echo "?")
  corpus=$(find "$OUT/corpus/$h" -type f | wc -l)
  crashes=$(find "$OUT/crash/$h" -type f | wc -l)
  printf '%-18s %12s %10s %8s %8s\n' "$h" "$execs" "$features" "$corpus" "$crashes"
done
