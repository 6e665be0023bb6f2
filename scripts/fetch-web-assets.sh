#!/usr/bin/env bash
# Fetches the charting library the HTML report inlines (`lrdslam report`, `run --report`): uPlot
# (npm package uplot, MIT, pinned version and integrity) into data/web/:
#   data/web/uPlot.iife.min.js  data/web/uPlot.min.css  data/web/uPlot.LICENSE
# The report's own script and style are in web/ (tracked). Idempotent: does nothing when the files
# are there and newer than the tarball. Needs npm (Debian: apt-get install npm).
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGE="uplot"
VERSION="1.6.31"
INTEGRITY="sha512-sQZqSwVCbJGnFB4IQjQYopzj5CoTZJ4Br1fG/xdONimqgHmsacvCjNesdGDypNKFbrhLGIeshYhy89FxPF+H+w=="
WEB_DIR="data/web"
NPM_DIR="$WEB_DIR/npm"
TARBALL="$NPM_DIR/$PACKAGE-$VERSION.tgz"
FILES=(uPlot.iife.min.js uPlot.min.css)

# shellcheck source=scripts/npm-fetch.sh
source "scripts/npm-fetch.sh"

die() { echo "fetch-web-assets: $*" >&2; exit 1; }

up_to_date() {
  local f
  [ -f "$TARBALL" ] || return 1
  for f in "${FILES[@]}" uPlot.LICENSE; do
    [ -f "$WEB_DIR/$f" ] && [ "$WEB_DIR/$f" -nt "$TARBALL" ] || return 1
  done
}
if up_to_date; then
  echo "fetch-web-assets: up to date ($WEB_DIR/{$(IFS=,; echo "${FILES[*]}")})"
  exit 0
fi

npm_fetch_verified "$PACKAGE" "$VERSION" "$INTEGRITY" "$NPM_DIR" "$TARBALL"

# -m: stamped now, so that the files are newer than the tarball for the check above.
tar -xzmf "$TARBALL" -C "$WEB_DIR" --strip-components=2 --no-same-permissions "${FILES[@]/#/package/dist/}"
tar -xzOf "$TARBALL" package/LICENSE >"$WEB_DIR/uPlot.LICENSE"
chmod 0644 "${FILES[@]/#/$WEB_DIR/}" "$WEB_DIR/uPlot.LICENSE"
echo "fetch-web-assets: done ($WEB_DIR/{$(IFS=,; echo "${FILES[*]}")})"
