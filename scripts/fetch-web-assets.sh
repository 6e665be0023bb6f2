#!/usr/bin/env bash
# Fetches the libraries the HTML report inlines (`lrdslam report`, `run --report`), each an npm
# package at a pinned version with its integrity checked, into data/web/:
#   uPlot (npm uplot, MIT): the charts
#     data/web/uPlot.iife.min.js  data/web/uPlot.min.css  data/web/uPlot.LICENSE
#   three.js (npm three, MIT; r147, the last with a browser build and examples/js): the 3-D map
#     data/web/three.min.js  data/web/three.OrbitControls.js  data/web/three.LICENSE
# The report's own scripts and style are in web/ (tracked). Idempotent: does nothing when the files
# are there and newer than their tarball. Needs npm (Debian: apt-get install npm).
set -euo pipefail
cd "$(dirname "$0")/.."

WEB_DIR="data/web"
NPM_DIR="$WEB_DIR/npm"

# shellcheck source=scripts/npm-fetch.sh
source "scripts/npm-fetch.sh"

die() { echo "fetch-web-assets: $*" >&2; exit 1; }

# fetch_package PACKAGE VERSION INTEGRITY LICENSE_NAME PATH_IN_TARBALL:NAME...
fetch_package() {
  local package=$1 version=$2 integrity=$3 license=$4 pair
  shift 4
  local tarball="$NPM_DIR/$package-$version.tgz" fresh=1
  [ -f "$tarball" ] || fresh=0
  for pair in "$@" "x:$license"; do
    [ "$fresh" = 1 ] && [ -f "$WEB_DIR/${pair#*:}" ] && [ "$WEB_DIR/${pair#*:}" -nt "$tarball" ] || fresh=0
  done
  if [ "$fresh" = 1 ]; then
    echo "fetch-web-assets: $package@$version up to date"
    return
  fi
  npm_fetch_verified "$package" "$version" "$integrity" "$NPM_DIR" "$tarball"
  for pair in "$@"; do
    tar -xzOf "$tarball" "package/${pair%%:*}" >"$WEB_DIR/${pair#*:}" || die "$tarball has no package/${pair%%:*}"
  done
  tar -xzOf "$tarball" package/LICENSE >"$WEB_DIR/$license" || die "$tarball has no package/LICENSE"
  for pair in "$@" "x:$license"; do chmod 0644 "$WEB_DIR/${pair#*:}"; done
  echo "fetch-web-assets: $package@$version done"
}

fetch_package uplot 1.6.31 \
  "sha512-sQZqSwVCbJGnFB4IQjQYopzj5CoTZJ4Br1fG/xdONimqgHmsacvCjNesdGDypNKFbrhLGIeshYhy89FxPF+H+w==" \
  uPlot.LICENSE dist/uPlot.iife.min.js:uPlot.iife.min.js dist/uPlot.min.css:uPlot.min.css
fetch_package three 0.147.0 \
  "sha512-LPTOslYQXFkmvceQjFTNnVVli2LaVF6C99Pv34fJypp8NbQLbTlu3KinZ0zURghS5zEehK+VQyvWuPZ/Sm8fzw==" \
  three.LICENSE build/three.min.js:three.min.js examples/js/controls/OrbitControls.js:three.OrbitControls.js
