#!/usr/bin/env bash
# The rviz screenshot in docs/ (docs/images/rviz-lrdslam.png): a synthetic walking_xyz bag played
# into lrdslam_ros (full mode, dense map) and watched by rviz with ros/rviz/lrdslam.rviz, all under
# Xvfb; the screen is dumped with xwd and converted by tools/ros/xwd2png.py.
# Usage: scripts/rviz-screenshot.sh [OUT.png]    (after a release build; installs rviz, xvfb and
# x11-apps from Debian when missing)
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-docs/images/rviz-lrdslam.png}
BIN=build/release/bin
for p in rviz xvfb x11-apps; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends rviz xvfb x11-apps
    break
  fi
done
WORK=$(mktemp -d)
pids=()
cleanup() { for p in "${pids[@]}"; do kill -INT "$p" 2>/dev/null || true; done; sleep 2; rm -rf "$WORK"; }
trap cleanup EXIT

"$BIN/lrdslam" synth --preset walking_xyz --frames 300 --out "$WORK/seq" --bag "$WORK/seq.bag" >/dev/null
PORT=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI=http://127.0.0.1:$PORT ROS_HOSTNAME=127.0.0.1 ROS_HOME=$WORK/roshome DISPLAY=:97
Xvfb :97 -screen 0 1400x900x24 >/dev/null 2>&1 & pids+=($!)
roscore -p "$PORT" >/dev/null 2>&1 & pids+=($!)
sleep 5
"$BIN/lrdslam_ros" __name:=lrdslam _mode:=full _segmenter:=fnet _dense:=true _output_dir:="$WORK/out" \
  >"$WORK/node.log" 2>&1 & pids+=($!)
rviz -d ros/rviz/lrdslam.rviz >"$WORK/rviz.log" 2>&1 & pids+=($!)
sleep 15
rosbag play -q -d 2 -r 0.5 "$WORK/seq.bag"
sleep 8
xwd -root -silent -out "$WORK/screen.xwd"
mkdir -p "$(dirname "$OUT")"
/usr/bin/python3 tools/ros/xwd2png.py "$WORK/screen.xwd" "$OUT"
echo "wrote $OUT"
