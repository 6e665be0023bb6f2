#!/usr/bin/env bash
# Fetches MediaPipe's selfie-segmentation models (npm package @mediapipe/selfie_segmentation, pinned
# version and integrity) into data/models/npm/ and converts them with tools/tflite2onnx to
#   data/models/selfie_segmentation.onnx            input 1x3x256x256 (NCHW, RGB in [0, 1])
#   data/models/selfie_segmentation_landscape.onnx  input 1x3x144x256
# Idempotent: does nothing when both models are newer than the converter and the tflite files.
# Needs npm (Debian: apt-get install npm) and /usr/bin/python3 with python3-onnx and python3-flatbuffers.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGE="@mediapipe/selfie_segmentation"
VERSION="0.1.1675465747"
INTEGRITY="sha512-IxYxNhwE5VwOm52L1yoFWYLP7q9Pd+NJjzOC5tlepfvEGaY3o9hslhUrx9BgseqdfZtKSDtd/4NfCSMjNzQalA=="
NPM_DIR="data/models/npm"
TARBALL="$NPM_DIR/mediapipe-selfie_segmentation-$VERSION.tgz"
MODELS=(selfie_segmentation selfie_segmentation_landscape)
PYTHON=/usr/bin/python3

# shellcheck source=scripts/npm-fetch.sh
source "scripts/npm-fetch.sh"

die() { echo "fetch-models: $*" >&2; exit 1; }

# True when data/models/NAME.onnx exists and is newer than its tflite and every converter source.
up_to_date() {
  local out="data/models/$1.onnx" src
  [ -f "$out" ] && [ -f "$NPM_DIR/$1.tflite" ] && [ "$out" -nt "$NPM_DIR/$1.tflite" ] || return 1
  for src in tools/tflite2onnx/*.py; do
    [ "$out" -nt "$src" ] || return 1
  done
}

stale=()
for m in "${MODELS[@]}"; do
  up_to_date "$m" || stale+=("$m")
done
if [ ${#stale[@]} -eq 0 ]; then
  echo "fetch-models: up to date (data/models/{$(IFS=,; echo "${MODELS[*]}")}.onnx)"
  exit 0
fi

npm_fetch_verified "$PACKAGE" "$VERSION" "$INTEGRITY" "$NPM_DIR" "$TARBALL"

# Extract only what is stale (-m: stamped now, not with the package's 1985 times, so the check above
# sees each tflite as newer than the model converted from it before).
files=()
for m in "${stale[@]}"; do files+=("package/$m.tflite"); done
tar -xzmf "$TARBALL" -C "$NPM_DIR" --strip-components=1 --no-same-permissions "${files[@]}"
chmod 0644 "${files[@]/#package\//$NPM_DIR/}"

license=$(tar -tzf "$TARBALL" | grep -m1 -E '^package/(LICEN[CS]E|COPYING)[^/]*$' || true)
if [ -n "$license" ]; then
  tar -xzOf "$TARBALL" "$license" >data/models/selfie_segmentation.LICENSE
else
  declared=$(tar -xzOf "$TARBALL" package/package.json |
             "$PYTHON" -c 'import json, sys; print(json.load(sys.stdin).get("license", "unknown"))')
  echo "fetch-models: note: the package has no LICENSE file; its package.json declares license $declared"
fi

for m in "${stale[@]}"; do
  echo "fetch-models: converting $NPM_DIR/$m.tflite -> data/models/$m.onnx"
  "$PYTHON" -m tools.tflite2onnx "$NPM_DIR/$m.tflite" "data/models/$m.onnx" --input-name input
done
echo "fetch-models: done"
