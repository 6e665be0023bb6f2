#include "lrd/runner/run_recorder.h"

#include <fmt/format.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <opencv2/imgcodecs.hpp>

#include "lrd/io/image_file.h"
#include "lrd/util/error.h"

namespace lrd::runner {

RunRecorder::RunRecorder(const io::FrameSource& sequence, std::size_t frames, bool progress,
                         std::optional<std::filesystem::path> save_masks)
    : sequence_(sequence), bar_(frames, progress), save_masks_(std::move(save_masks)) {
  log_.reserve(frames);
}

void RunRecorder::on_frame(const events::FrameTracked& e) {
  const auto index = static_cast<std::size_t>(e.frame_id);
  log_.push_back(
      {index, e.timestamp, e.state, e.timing, e.inliers, e.mask_frame, e.mask_age, e.geometric_keypoints});
  if (save_masks_) {
    const std::filesystem::path file = *save_masks_ / sequence_.entry(index).rgb_path.filename();
    const cv::Mat m = e.mask.empty() ? cv::Mat::zeros(e.grey.size(), CV_8UC1) : e.mask;
    io::write_image_file(file, m, {}, util::Sync::no);  // one a frame: not synced one by one
  }
  bar_.update(log_.size(), fmt::format("{} ({} inliers)", tracking::to_string(e.state), e.inliers));
}

std::vector<FrameLog> RunRecorder::take_log() {
  bar_.finish();
  return std::move(log_);
}

FlagScorer::FlagScorer(const io::FrameSource& sequence, std::filesystem::path mask_folder,
                       const features::OrbParams& orb, int stride)
    : sequence_(sequence), mask_folder_(std::move(mask_folder)), extractor_(orb), stride_(stride) {}

void FlagScorer::on_frame(const events::FrameTracked& e) {
  const auto index = static_cast<std::size_t>(e.frame_id);
  if (index % static_cast<std::size_t>(stride_) != 0) return;
  const std::filesystem::path mask_file = mask_folder_ / sequence_.entry(index).rgb_path.filename();
  const cv::Mat truth = cv::imread(mask_file.string(), cv::IMREAD_UNCHANGED);
  if (truth.empty() || truth.type() != CV_8UC1 || truth.size() != e.grey.size()) return;
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  // On this (low-priority) thread alone: the extractor's parallel levels would otherwise run on
  // TBB's shared workers at normal priority, beside tracking's own extraction.
  static tbb::task_arena single_thread(1);
  single_thread.execute([&] { extractor_.extract(e.grey, cv::Mat(), keypoints, descriptors); });
  ++score_.frames;
  const FlagScore before = score_;
  for (const cv::KeyPoint& kp : keypoints) {
    const int u = std::clamp(cvRound(kp.pt.x), 0, truth.cols - 1);
    const int v = std::clamp(cvRound(kp.pt.y), 0, truth.rows - 1);
    const std::uint8_t t = truth.at<std::uint8_t>(v, u);
    const bool flagged = !e.mask.empty() && e.mask.at<std::uint8_t>(v, u) != 0;
    if (t != 0)
      (flagged ? score_.true_positive : score_.false_negative)++;
    else
      (flagged ? score_.false_positive : score_.true_negative)++;
    // Mask values: 1 person, 2 moved object, 3 balloon (synth::MaskLabel).
    const auto count = [&](std::size_t& on, std::size_t& caught) {
      ++on;
      caught += flagged ? 1 : 0;
    };
    if (t == 1) count(score_.person, score_.person_flagged);
    if (t == 2) count(score_.moved_object, score_.moved_object_flagged);
    if (t == 3) count(score_.balloon, score_.balloon_flagged);
  }
  per_frame_.push_back({index, score_.true_positive - before.true_positive,
                        score_.false_positive - before.false_positive,
                        score_.false_negative - before.false_negative});
}

FlagScore FlagScorer::score() const {
  return score_;
}

}  // namespace lrd::runner
