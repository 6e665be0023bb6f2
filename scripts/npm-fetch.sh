# Sourced by scripts/fetch-models.sh and scripts/fetch-web-assets.sh (not run on its own).
# npm_fetch_verified PACKAGE VERSION INTEGRITY DIR TARBALL: leaves npm's tarball of PACKAGE@VERSION
# at TARBALL (fetched into DIR unless it is there) whose sha512 is INTEGRITY (npm's "sha512-..."
# form), or calls the caller's die() with one line. Needs npm and /usr/bin/python3.
npm_fetch_verified() {
  local package=$1 version=$2 integrity=$3 dir=$4 tarball=$5 log actual tag=${0##*/}
  mkdir -p "$dir"
  if [ ! -f "$tarball" ]; then
    command -v npm >/dev/null || die "npm not found; install it (apt-get install npm) to fetch $package@$version"
    echo "${tag%.sh}: fetching $package@$version from the npm registry"
    if ! log=$(npm pack "$package@$version" --pack-destination "$dir" --loglevel=error \
                   --fetch-retries=1 --fetch-timeout=30000 2>&1 >/dev/null); then
      die "npm could not fetch $package@$version (registry unreachable?): $(echo "$log" | grep -m1 -i 'err' || echo "$log" | tail -n1)"
    fi
    [ -f "$tarball" ] || die "npm pack did not produce $tarball"
  fi
  actual="sha512-$(/usr/bin/python3 -c 'import base64, hashlib, sys
print(base64.b64encode(hashlib.sha512(open(sys.argv[1], "rb").read()).digest()).decode())' "$tarball")"
  if [ "$actual" != "$integrity" ]; then
    rm -f "$tarball"
    die "integrity mismatch for $package@$version (expected $integrity, got $actual); removed $tarball"
  fi
}
