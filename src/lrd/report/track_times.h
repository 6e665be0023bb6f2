#pragma once
// track_times.txt (runner::write_track_times) read back: one row per frame.
#include <filesystem>
#include <string>
#include <vector>

namespace lrd::report {

struct FrameTimes {
  long index = 0;
  double timestamp = 0.0;
  // extraction, segmentation, mask_wait, geometry, tracking, waiting, mapping (ms); total is
  // their sum less segmentation, which runs in its own thread.
  std::vector<double> stage_ms;
  double total_ms = 0.0;
  std::string state;  // tracking::to_string(TrackingState)
  int inliers = 0;
  long mask_frame = -1;
  long mask_age = -1;
  int dynamic_keypoints = 0;
};

// The stage columns of track_times.txt, in order.
[[nodiscard]] const std::vector<std::string>& stage_names();

// Throws lrd::Error naming FILE (and FILE:LINE for a row with a wrong field count or a
// non-numeric field) when it cannot be read or its header is not track_times.txt's.
[[nodiscard]] std::vector<FrameTimes> read_track_times(const std::filesystem::path& file);

}  // namespace lrd::report
