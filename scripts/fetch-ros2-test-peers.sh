#!/usr/bin/env bash
# Fetches the npm packages the ROS 2 bag cross-check uses (tests/ros2/, tests/python/
# test_cli_ros2_peers.py): Foxglove's MCAP library and ROS 2 CDR serialisation, an implementation
# that is not ours, to write bags our reader must accept and to read the bags we write. Each
# package is pinned with its integrity checked (npm pack + sha512, scripts/npm-fetch.sh) into
# data/npm-ros2/tarballs/, then unpacked into data/npm-ros2/node_modules/ without the registry
# (the whole dependency closure is listed here, so no npm install resolves anything).
# Idempotent: does nothing when every package is unpacked from its tarball. Needs npm.
set -euo pipefail
cd "$(dirname "$0")/.."

ROOT="data/npm-ros2"
TARBALLS="$ROOT/tarballs"
MODULES="$ROOT/node_modules"

# shellcheck source=scripts/npm-fetch.sh
source "scripts/npm-fetch.sh"

die() { echo "fetch-ros2-test-peers: $*" >&2; exit 1; }

# fetch_and_unpack PACKAGE VERSION INTEGRITY [MODULES_DIR]: unpacked into MODULES_DIR/PACKAGE
# (default $MODULES, the top level; a package's own node_modules/ for a version only it uses).
fetch_and_unpack() {
  local package=$1 version=$2 integrity=$3 modules=${4:-$MODULES}
  # npm pack names a scoped package's tarball without the @ and with - for /.
  local flat=${package#@}
  local tarball="$TARBALLS/${flat//\//-}-$version.tgz" target="$modules/$package"
  if [ -f "$target/.from-tarball" ] && [ "$(cat "$target/.from-tarball")" = "$version $integrity" ]; then
    return
  fi
  npm_fetch_verified "$package" "$version" "$integrity" "$TARBALLS" "$tarball"
  rm -rf "$target"
  mkdir -p "$target"
  tar -xzf "$tarball" -C "$target" --strip-components=1 || die "cannot unpack $tarball"
  echo "$version $integrity" >"$target/.from-tarball"
  echo "fetch-ros2-test-peers: $package@$version unpacked"
}

# MCAP: McapWriter, McapIndexedReader (and their dependencies).
fetch_and_unpack @mcap/core 2.2.2 \
  "sha512-W4NFiyqQlJsNjw8JxAAQ872u0xLWJy0GFC3YFm8bTLbNs+HdDWe8DwBqznr0MGYpWtw+AX8XzHWB5Y9rLEGJJg=="
fetch_and_unpack @foxglove/crc 0.0.3 \
  "sha512-DjIZsnL3CyP/yQ/vUYA9cjrD0a/8YXejI5ZmsaOiT16cLfZcTwaCxIN01/ys4jsy+dZCQ/9DnWFn7AEFbiMDaA=="
fetch_and_unpack heap-js 2.7.2 \
  "sha512-hl3ckmCs5hLAkk9YYqy0z6bqw78eZ4/JddC7mG7Xf/6heEb4v99EkO7sCJslxt62lmCMp+K47OWDKtSuUaqI+g=="
fetch_and_unpack tslib 2.9.1 \
  "sha512-a4Ux9VKuIMHsOS7ENbEq6hK2ZGYIT27Rtl0E4eD9KqwxhKiQeMZE/9xb3IdYwWaSOyIBQLExhQgXDTYoiCxnWA=="
# ROS 2 CDR: MessageWriter, MessageReader.
fetch_and_unpack @foxglove/rosmsg2-serialization 3.1.0 \
  "sha512-N43XcoYEwd2bCTWwx49VjN9UuK1+3njhWvbXNBrrHY83KBkgj7BHkDQqnDbr69R0nFAJR0ufTFqJoj054tuO7g=="
fetch_and_unpack @foxglove/cdr 3.5.0 \
  "sha512-trj8uB+J71SuW9g8TbbDgTbvqrmUHQjh5uhqBAraBhg4hxm7aG9AFPvz34yJ/XZnl28x0NuLjptJYKNSUlgM9Q=="
fetch_and_unpack @foxglove/message-definition 0.5.0 \
  "sha512-B/2GvWn4wRSsPDywcmy6uNXgAfZRhiOAnmy3qAaS6MHVqiHQqs/RoDsoW6Gw9sXSweJpeH5qAqAihvm1pR9Thg=="
fetch_and_unpack @foxglove/rostime 1.1.3 \
  "sha512-Gr3Xy4sNbo2NcXg0tBHb/jVUqIcDyZ1kgHj9dB7K+Y1A7AQ0oSCmSXIuf8oqeteSIs0pl8BJOWEwAtLNC99Izg=="
# The official message definitions (sensor_msgs, std_msgs, tf2_msgs, ...) and their parser.
fetch_and_unpack @foxglove/rosmsg 5.0.5 \
  "sha512-+qY6xW+4HdbPI3ItAlFFMjXgAiplXyRsv+kqdBk8OcWGH38BmEd7s6v/VnCkbYovAoB5rfR5giuKfmPRNzwbrA=="
fetch_and_unpack md5-typescript 1.0.5 \
  "sha512-ovAc4EtiNt2dY8JPhPr/wkC9h4U5k/nuClNVcG0Ga3V1rMlYpAY24ZaaymFXJlz+ccJ6UMPo3FSaVKe7czBsXw=="
fetch_and_unpack @foxglove/rosmsg-msgs-common 3.2.3 \
  "sha512-i+pdyOAGb7DHDaIRON+zGy2izW3kQewRImOcHGzGWib3dOaTvoI5RoapOykDQyND9L9E8QbLntCSSAKHBBfOsg=="
# ROS 2 over DDS (tests/ros2/ros2_listener.cjs): Foxglove's pure-JavaScript RTPS participant and
# ROS 2 node, an independent subscriber to our node. They need older majors of cdr, rosmsg and
# rosmsg2-serialization than the bag tools above, so these (and avl 1.5, as avl 1.6 is ESM-only and
# rtps require()s it) are nested under @foxglove/ros2/node_modules/, where Node resolves them first
# from ros2 and rtps; tslib (which ros2's dist requires without declaring it), @foxglove/rostime and
# md5-typescript resolve from the top level.
fetch_and_unpack @foxglove/ros2 1.0.8 \
  "sha512-R7FGNDH/8A6CEaWLe2ta+t0GlmHYwm7JyS0GRKTzfD1Z6Af+DL+AzKyk1bovvtZT2/tJQhy+UACurjGDlTN82g=="
ROS2_NESTED="$MODULES/@foxglove/ros2/node_modules"
fetch_and_unpack @foxglove/rtps 1.6.0 \
  "sha512-iPcG1Q3sjNxBOgnPHteHukxopSymHhscZiury0dJZTz7gRLJ6SbgcG5qHytSrmQyTmOyynHjNinWo00hetIEdg==" "$ROS2_NESTED"
fetch_and_unpack @foxglove/cdr 2.1.0 \
  "sha512-2jNHDt3EitikewW7pDzkh0BLx1qc1clXmgdbNRI8g4lpaib4EZ9pFdcVtbJ8iP9/yev6xustPSHqRPVWwtuFzQ==" "$ROS2_NESTED"
fetch_and_unpack @foxglove/rosmsg2-serialization 1.1.1 \
  "sha512-J4xhO3hca5D5MGcHt9GrwQfZh7IRRMr94ty12E7WEUhv3KAAw4vHU8Ei89CYj9yPQSwRC0Vpr7QyxDXEMQ0v3w==" "$ROS2_NESTED"
fetch_and_unpack @foxglove/rosmsg 3.1.0 \
  "sha512-uvL3a3PRusrQw4tg91tsXfPMCWjsKV35nAaHkzPqRt4bZRzO2DAUMavCltjRux5Hc8WLPYWt77iUSk3KfxqUZQ==" "$ROS2_NESTED"
fetch_and_unpack avl 1.5.3 \
  "sha512-1qcOJeREIosJxIBof2nefabU9+Y3wCxXBb3ElQmNVOHP+Hu2BLWAh8CpU7xFnJNDMVBt2H5UOE2S/B7MEqhTsg==" "$ROS2_NESTED"
fetch_and_unpack eventemitter3 4.0.7 \
  "sha512-8guHBZCwKnFhYdHr2ysuRWErTwhoN2X8XELRlrRwpmfeY2jjuUN4taQMsULKUVo1K4DvZl+0pgfyoysHxvmvEw==" "$ROS2_NESTED"
echo "fetch-ros2-test-peers: done ($MODULES)"
