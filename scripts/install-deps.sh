#!/usr/bin/env bash
# Installs the Debian (bookworm) packages lrd-slam needs. Idempotent: skips apt entirely when
# everything is already installed. Run as root (or via sudo).
#   scripts/install-deps.sh          everything: build, every feature, the tests (scripts/run-tests.sh)
#   scripts/install-deps.sh --main   only what building the CLI and running the default job need
#                                    (scripts/run-default.sh): no ROS, DDS, Python, Slurm, browser
#                                    or training packages; the features that need them say what to
#                                    install when they are missing (docs/install.md)
set -euo pipefail

MAIN=(
  # toolchain
  build-essential cmake ninja-build pkg-config git
  # libraries
  libopencv-dev libeigen3-dev libceres-dev libyaml-cpp-dev libcli11-dev libspdlog-dev libfmt-dev zlib1g-dev
  nlohmann-json3-dev libtbb-dev
  libgtest-dev libgmock-dev libbenchmark-dev  # configure-time only unless the tests or benchmarks are built
  # ROS 2 bags (rosbag2/, our own reader and writer): sqlite3 storage, MCAP's zstd and LZ4 chunks
  libsqlite3-dev libzstd-dev liblz4-dev
  liboctomap-dev  # the occupancy map
  # Real photographs used as textures by the synthetic benchmark (lrdslam synth)
  opencv-doc gnome-backgrounds mate-backgrounds
)

FEATURES=(
  clang-format-14  # the format check (scripts/check-format.sh, a ctest test)
  clang-14 libclang-rt-14-dev  # libFuzzer and its sanitizers: the fuzz preset (bench/fuzz/run.sh)
  graphviz         # docs/architecture: the picture from its text source
  octomap-tools    # octovis-free tools to inspect .bt files
  zstd lz4  # their command-line tools: the Node.js cross-check (tests/ros2/) decompresses chunks with them
  # Python side (tests, reference evaluators, FNet training) — always /usr/bin/python3
  python3 python3-numpy python3-opencv python3-pytest python3-yaml
  python3-torch python3-onnx python3-pil  # FNet: training, ONNX export fix-up, VOC palette labels
  python3-flatbuffers  # tools/tflite2onnx reads TFLite models (scripts/fetch-models.sh)
  python3-dev pybind11-dev  # the Python module (python/): pybind11 bindings for /usr/bin/python3
  slurmctld slurmd slurm-client  # `lrdslam sweep --executor slurm` and its test (a real Slurm on 127.0.0.1)
  # ROS 1: rosbag input (`run --bag`, `synth --bag`) and the lrdslam_ros node with its
  # tests (roscore, rosbag play, rostopic). rosbag's headers pull in bookworm's ROS 2 pluginlib,
  # whose rcpputils/rcutils headers are named here because the build includes them.
  ros-core libroscpp-dev librosbag-storage-dev libmessage-filters-dev libcv-bridge-dev
  libimage-transport-dev libtf2-ros-dev libtf2-msgs-dev libsensor-msgs-dev libnav-msgs-dev
  libgeometry-msgs-dev libvisualization-msgs-dev libstd-msgs-dev libstd-srvs-dev
  librcpputils-dev librcutils-dev python3-rosbag
  python3-rospy python3-sensor-msgs python3-geometry-msgs python3-nav-msgs python3-std-srvs python3-std-msgs
  python3-visualization-msgs python3-tf2-msgs  # the node tests publish, subscribe and call services
  # ROS 2 (ros2/): the lrdslam_ros2 node and `lrdslam ros2-play` on Cyclone DDS, the DDS under
  # rmw_cyclonedds_cpp; idlc (cyclonedds-tools) compiles the messages' IDL
  cyclonedds-dev cyclonedds-tools
  # The HTML report's test opens a report in headless Chromium
  chromium fonts-dejavu-core
)

PACKAGES=("${MAIN[@]}")
WANT_NPM=1
case "${1:-}" in
  --main) WANT_NPM=0 ;;
  "") PACKAGES+=("${FEATURES[@]}") ;;
  *) echo "install-deps: unknown option '$1' (usage: scripts/install-deps.sh [--main])" >&2; exit 2 ;;
esac

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# npm fetches MediaPipe's selfie model (scripts/fetch-models.sh), the report's charting libraries
# and the ROS 2 test peers. Machines that already have Node.js with npm keep theirs; Debian's npm
# package is the fallback.
if [ "$WANT_NPM" = 1 ] && ! command -v npm >/dev/null 2>&1; then missing+=(npm); fi

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${#missing[@]} package(s): ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: done"
