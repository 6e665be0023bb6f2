#pragma once
// The CLI runner's subscribers (events/event_publisher.h): they watch the run from the
// publisher's thread, so nothing they do is timed as tracking.
//  - RunRecorder: the per-frame log (track_times.txt, summary.json), the progress bar and
//    --save-masks;
//  - FlagScorer: the dynamic keypoint flags against the synthetic benchmark's ground-truth masks,
//    on every n-th frame, over the keypoints an unmasked extractor finds there.
#include <filesystem>
#include <mutex>
#include <optional>
#include <vector>

#include "lrd/events/event_publisher.h"
#include "lrd/features/orb_extractor.h"
#include "lrd/io/frame_source.h"
#include "lrd/runner/progress_bar.h"
#include "lrd/runner/sequence_runner.h"

namespace lrd::runner {

class RunRecorder final : public events::Subscriber {
 public:
  RunRecorder(const io::FrameSource& sequence, std::size_t frames, bool progress,
              std::optional<std::filesystem::path> save_masks);
  void on_frame(const events::FrameTracked& e) override;
  // After System::shutdown (the publisher has delivered everything).
  [[nodiscard]] std::vector<FrameLog> take_log();

 private:
  const io::FrameSource& sequence_;
  ProgressBar bar_;
  std::optional<std::filesystem::path> save_masks_;
  std::vector<FrameLog> log_;
};

class FlagScorer final : public events::Subscriber {
 public:
  FlagScorer(const io::FrameSource& sequence, std::filesystem::path mask_folder,
             const features::OrbParams& orb, int stride);
  void on_frame(const events::FrameTracked& e) override;
  [[nodiscard]] FlagScore score() const;
  [[nodiscard]] const std::vector<FrameFlags>& per_frame() const { return per_frame_; }

 private:
  const io::FrameSource& sequence_;
  std::filesystem::path mask_folder_;
  features::OrbExtractor extractor_;
  int stride_;
  FlagScore score_;
  std::vector<FrameFlags> per_frame_;
};

}  // namespace lrd::runner
