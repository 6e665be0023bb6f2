#pragma once
// The frames an HTML report shows (docs/report.md), chosen while the run goes and drawn at its end:
// the most keypoints removed by the geometry check, the oldest masks used, and the largest error
// against ground truth (among evenly spaced frames kept as the run goes, since errors are only
// known once the trajectory is aligned). Bounded: at most kPerReason frames per reason, and the
// evenly spaced pool never holds more than kPool frames. With the dense map, also the background
// repair (§2.8) of the kRepairs keyframes with the most dynamic pixels, before and after.
#include <cstdint>
#include <filesystem>
#include <map>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "lrd/events/event_publisher.h"
#include "lrd/events/map_snapshot.h"
#include "lrd/io/trajectory.h"
#include "lrd/runner/sequence_runner.h"

namespace lrd::runner {

class SampleFrameRecorder final : public events::Subscriber {
 public:
  static constexpr std::size_t kPerReason = 8;
  static constexpr std::size_t kPool = 48;
  static constexpr std::size_t kRepairs = 6;

  void on_frame(const events::FrameTracked& e) override;
  void on_dense_map(const events::DenseMapUpdated& e) override;

  // Draws the chosen frames (dynamic mask tinted red, kept keypoints green, removed ones magenta)
  // as JPEGs into `folder` with frames.json naming them and why each was chosen, and the
  // yardstick Y timed on the pool's frames. `ground_truth`
  // and `trajectory` pick the largest errors (none without ground truth). After System::shutdown.
  // `flags`: the scored frames' dynamic flags (FlagScorer; empty without ground-truth masks).
  void write(const std::filesystem::path& folder, const io::Trajectory& trajectory,
             const std::optional<io::Trajectory>& ground_truth, const std::vector<FrameFlags>& flags) const;

 private:
  struct Sample {
    std::uint64_t frame_id = 0;
    double timestamp = 0.0;
    int mask_age = -1;
    std::string state;
    cv::Mat grey, mask;
    std::vector<cv::Point2f> kept, removed;
  };
  using Ranked = std::vector<std::pair<double, std::uint64_t>>;            // (score, frame), best first
  bool rank(Ranked& ranked, double score, const events::FrameTracked& e);  // true: kept
  void keep(const events::FrameTracked& e);
  void forget_unused();

  std::map<std::uint64_t, Sample> samples_;
  Ranked most_removed_, oldest_mask_;
  std::vector<std::uint64_t> pool_;  // evenly spaced frames for the largest errors
  std::uint64_t pool_stride_ = 1;
  struct Repair {
    double timestamp = 0.0;
    std::size_t dynamic_pixels = 0, filled_pixels = 0;
    cv::Mat picture;  // colour and depth, before and after, in one image
  };
  std::vector<Repair> repairs_;  // most dynamic pixels first
};

// The sparse map's points (positions only) for the report's 3-D view: `run --report` writes them
// as report_frames/sparse_map.ply. Throws lrd::Error naming the file when it cannot be written.
void write_sparse_map_ply(const std::filesystem::path& file, const events::MapSnapshot& map);

}  // namespace lrd::runner
