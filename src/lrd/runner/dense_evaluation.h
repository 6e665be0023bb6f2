#pragma once
// Judging the dense stage on a sequence with ground truth (the bars in bench/results/dense.md):
// background repair against the synthetic benchmark's static/depth images, and the dense map
// against its scene.ply.
#include <filesystem>
#include <mutex>
#include <optional>
#include <unordered_map>
#include <vector>

#include "lrd/camera/image_undistorter.h"
#include "lrd/camera/pinhole_camera.h"
#include "lrd/dense/background_repairer.h"
#include "lrd/dense/point_cloud.h"
#include "lrd/eval/map_accuracy.h"
#include "lrd/events/event_publisher.h"
#include "lrd/io/frame_source.h"
#include "lrd/io/trajectory.h"
#include "lrd/io/tum_sequence.h"

namespace lrd::runner {

// A subscriber of a run's dense-map events: writes the repaired keyframes (--save-repaired) and
// compares the filled depths with the static scene's depth where the sequence has one
// (static/depth/).
class RepairRecorder final : public events::Subscriber {
 public:
  // `camera`: the run's; with a lens distortion the dense stage works on undistorted keyframes
  // (camera/image_undistorter.h), and static/depth is resampled alike before comparing.
  RepairRecorder(const io::FrameSource& sequence, const camera::PinholeCamera& camera,
                 std::optional<std::filesystem::path> save_dir);

  void on_dense_map(const events::DenseMapUpdated& e) override {
    if (e.repair) record(e.timestamp, e.keyframe, *e.repair);
  }
  // Each repaired keyframe (on the publisher's thread).
  void record(double timestamp, const dense::RgbdView& keyframe, const dense::RepairResult& repair);

  [[nodiscard]] bool has_truth() const { return has_truth_; }
  // Compares the recorded repairs with static/depth (read only now, after the run, so judging
  // does not load the dense thread): median |repaired depth - static depth| over the filled
  // pixels (m), and how many pixels were compared.
  struct DepthError {
    double median = 0.0;
    std::size_t pixels = 0;
  };
  [[nodiscard]] DepthError depth_error() const;

 private:
  const io::FrameSource& sequence_;
  double depth_factor_;
  camera::ImageUndistorter undistorter_;
  std::optional<std::filesystem::path> save_dir_;
  bool has_truth_ = false;
  std::unordered_map<long long, std::size_t> by_stamp_;  // rgb timestamp in microseconds -> entry
  // The filled pixels of each repaired keyframe: its static depth file, pixel indices, depths.
  struct Filled {
    std::filesystem::path truth;
    std::vector<int> pixels;
    std::vector<float> depths;
  };
  mutable std::mutex mutex_;
  std::vector<Filled> filled_;
};

}  // namespace lrd::runner
