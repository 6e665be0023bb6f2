#!/usr/bin/env bash
# Trains the shipped bag-of-words vocabulary, vocab/orb_vocab.lrdv, exactly as it was trained
# (docs/place-recognition.md). Not part of CI: the result is committed.
#
#   bash scripts/train-vocab.sh [BUILD_DIR]     (default build/release; needs `lrdslam`)
#
# Training images: real photographs from Debian packages (desktop backgrounds of GNOME and MATE,
# OpenCV's sample images), so that place recognition works on real imagery, plus synthetic frames
# of our benchmark's room rendered with seeds 5000.. (disjoint from the evaluation seeds 1-99).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build/release}
LRDSLAM="$BUILD/bin/lrdslam"
[ -x "$LRDSLAM" ] || { echo "train-vocab: $LRDSLAM not built (cmake --preset release && cmake --build build/release)" >&2; exit 1; }

SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
missing=()
for p in gnome-backgrounds mate-backgrounds opencv-doc; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
  $SUDO apt-get update -qq && $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

WORK=out/vocab
mkdir -p "$WORK"
if [ ! -d "$WORK/synth/JPEGImages" ]; then
  "$LRDSLAM" synth --export-voc "$WORK/synth" --images 240 --seed 5000
fi
LIST="$WORK/images.txt"
{
  find /usr/share/backgrounds/gnome /usr/share/backgrounds/mate -type f \( -iname '*.jpg' -o -iname '*.png' -o -iname '*.jpeg' \) | LC_ALL=C sort
  find /usr/share/doc/opencv-doc/examples/data -type f \( -iname '*.jpg' -o -iname '*.png' \) -size +20k | LC_ALL=C sort
  find "$(pwd)/$WORK/synth/JPEGImages" -type f -iname '*.jpg' | LC_ALL=C sort
} > "$LIST"
echo "train-vocab: $(wc -l < "$LIST") images"
mkdir -p vocab
"$LRDSLAM" vocab train --images "$LIST" --out vocab/orb_vocab.lrdv --k 10 --levels 5 --features 1000 --seed 24301
"$LRDSLAM" vocab info vocab/orb_vocab.lrdv
sha256sum vocab/orb_vocab.lrdv
