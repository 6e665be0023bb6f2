#pragma once
// Writes a synthetic sequence to disk in the TUM RGB-D layout, plus the ground truth no real
// dataset has (per-pixel dynamic masks, the actor-free static view):
//   rgb/ depth/ rgb.txt depth.txt associations.txt groundtruth.txt settings.yaml
//   mask/ (0 static, 1 person, 2 moved object)  static/rgb/ static/depth/  sequence.json
#include <filesystem>
#include <functional>
#include <string>

#include "lrd/synth/synthetic_sequence.h"

namespace lrd::synth {

struct SynthSummary {
  int frames = 0;
  double seconds = 0.0;
  double mean_dynamic_fraction = 0.0;  // of the image covered by actors
  double median_dynamic_fraction = 0.0;
  double max_dynamic_fraction = 0.0;
  double frames_with_20_to_50_percent = 0.0;  // fraction of frames
};

// Renders and writes every frame (in parallel; the files do not depend on the thread count).
// `progress(done, total)` is called from the writing threads, serialised.
SynthSummary write_sequence(const SyntheticSequence& sequence, const std::filesystem::path& out,
                            const std::function<void(int, int)>& progress = {});

// A frame's image file name in rgb/, depth/, mask/ and static/: its timestamp, "1700000000.033333.png".
[[nodiscard]] std::string frame_file_name(double stamp);

// ORB-SLAM2-format settings for the synthetic camera (fr3 intrinsics, no distortion).
void write_orbslam_settings(const std::filesystem::path& file, const camera::PinholeCamera& camera);

}  // namespace lrd::synth
