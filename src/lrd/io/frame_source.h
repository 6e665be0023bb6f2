#pragma once
// Where a run's frames come from: a TUM sequence folder (io::TumSequence) or, in a build with ROS,
// a rosbag (lrd_ros::BagSequence). The prefetcher and the runner see only this interface, so the
// library itself needs no ROS.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

#include "lrd/io/rgbd_frame.h"
#include "lrd/io/trajectory.h"

namespace lrd::io {

// The camera a source carries with its frames (a bag's camera_info): intrinsics and distortion
// (k1, k2, p1, p2, k3) in OpenCV's order, and the image size.
struct SourceCamera {
  int width = 0, height = 0;
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;
  double readout_time = 0.0;  // s: a rolling shutter's (camera::PinholeCamera::readout_time)
  std::string origin;         // where it was read, for the run's "camera:" line
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;

  [[nodiscard]] virtual std::size_t size() const = 0;
  // Frame i's timestamps and image names. A folder names its files; a bag names each frame like
  // the folder layout would ("rgb/STAMP.png"), so saved masks and repaired keyframes are named
  // alike from both.
  [[nodiscard]] virtual const FrameEntry& entry(std::size_t i) const = 0;
  // Decodes frame i (colour as 8-bit BGR, depth as metres, 0 = no measurement). depth_factor is
  // a depth PNG's value per metre; a source whose depth carries its unit ignores it. Throws
  // lrd::Error naming the file (or the bag and topic) and the problem. Called from one thread.
  [[nodiscard]] virtual RgbdFrame load_rgbd(std::size_t i, double depth_factor) const = 0;
  // Names frame i's colour image in an error message: its file, or "BAG: TOPIC at STAMP".
  [[nodiscard]] virtual std::string describe(std::size_t i) const = 0;
  // The source for messages: the folder or the bag file.
  [[nodiscard]] virtual std::filesystem::path path() const = 0;
  // The folder that may hold the synthetic benchmark's extra files (settings.yaml, sequence.json,
  // mask/, static/, scene.ply); none for a bag.
  [[nodiscard]] virtual std::optional<std::filesystem::path> folder() const = 0;
  // The ground-truth trajectory when the source has one, and where it was read (for messages).
  [[nodiscard]] virtual std::optional<Trajectory> ground_truth() const = 0;
  [[nodiscard]] virtual std::string ground_truth_origin() const = 0;
  // The camera the source carries, if any (a folder carries none: see runner::resolve_config).
  [[nodiscard]] virtual std::optional<SourceCamera> camera() const { return std::nullopt; }
  // True for frames of our synthetic benchmark rendered on the fly (no folder): a semantic run
  // then gets the network trained on its renders, as a synthetic folder does (sequence.json).
  [[nodiscard]] virtual bool synthetic_benchmark() const { return false; }
};

}  // namespace lrd::io
