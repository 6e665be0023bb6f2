#include "lrd/runner/sample_frames.h"

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>

#include "lrd/dense/ply_io.h"
#include "lrd/eval/ate.h"
#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"
#include "lrd/util/yardstick.h"

namespace lrd::runner {
namespace fs = std::filesystem;

namespace {

// The frame as the report shows it: dynamic pixels tinted red, keypoints used for tracking as
// green circles, those the geometry check removed as magenta crosses.
cv::Mat draw(const cv::Mat& grey, const cv::Mat& mask, const std::vector<cv::Point2f>& kept,
             const std::vector<cv::Point2f>& removed) {
  cv::Mat bgr;
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  if (!mask.empty()) {
    cv::Mat red(bgr.size(), bgr.type(), cv::Scalar(40, 40, 230)), tinted;
    cv::addWeighted(bgr, 0.55, red, 0.45, 0.0, tinted);
    tinted.copyTo(bgr, mask);
  }
  for (const cv::Point2f& p : kept) cv::circle(bgr, p, 3, cv::Scalar(60, 200, 60), 1, cv::LINE_AA);
  for (const cv::Point2f& p : removed)
    cv::drawMarker(bgr, p, cv::Scalar(230, 40, 230), cv::MARKER_TILTED_CROSS, 7, 2);
  return bgr;
}

void write_jpeg(const fs::path& file, const cv::Mat& bgr) {
  std::vector<std::uint8_t> jpeg;
  if (!cv::imencode(".jpg", bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, 85}))
    throw file_error(file, "cannot encode");
  util::write_file_bytes(file, std::string_view(reinterpret_cast<const char*>(jpeg.data()), jpeg.size()));
}

// Depth in metres as a colour picture (0-5 m, near = red; no measurement black).
cv::Mat depth_picture(const cv::Mat& depth) {
  cv::Mat scaled, picture;
  depth.convertTo(scaled, CV_8UC1, -255.0 / 5.0, 255.0);
  cv::applyColorMap(scaled, picture, cv::COLORMAP_JET);
  picture.setTo(cv::Scalar::all(0), depth <= 0.0f);
  return picture;
}

// Colour before | after over depth before | after, at half size: Fig. 12 of the paper.
cv::Mat repair_picture(const dense::RgbdView& keyframe, const dense::RepairResult& repair) {
  cv::Mat top, bottom, both, half;
  cv::hconcat(keyframe.bgr, repair.bgr, top);
  cv::hconcat(depth_picture(keyframe.depth), depth_picture(repair.depth), bottom);
  cv::vconcat(top, bottom, both);
  cv::resize(both, half, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  return half;
}

// Each estimated stamp's ATE error (TUM alignment), empty when there is no ground truth to align.
std::map<double, double> errors_by_stamp(const io::Trajectory& trajectory,
                                         const std::optional<io::Trajectory>& gt) {
  std::map<double, double> errors;
  if (!gt || trajectory.size() < 2) return errors;
  try {
    const eval::AteResult ate = eval::compute_ate(*gt, trajectory);
    for (std::size_t i = 0; i < ate.matches.size(); ++i)
      errors[trajectory[ate.matches[i].second].timestamp] = ate.errors[i];
  } catch (const Error&) {  // no stamps associate: no errors to rank by
  }
  return errors;
}

// Columns, as the page draws them.
nlohmann::json flags_json(const std::vector<FrameFlags>& flags) {
  nlohmann::json j = {{"frame", nlohmann::json::array()},
                      {"true_positive", nlohmann::json::array()},
                      {"false_positive", nlohmann::json::array()},
                      {"false_negative", nlohmann::json::array()}};
  for (const FrameFlags& f : flags) {
    j["frame"].push_back(f.frame);
    j["true_positive"].push_back(f.true_positive);
    j["false_positive"].push_back(f.false_positive);
    j["false_negative"].push_back(f.false_negative);
  }
  return j;
}

}  // namespace

void SampleFrameRecorder::on_frame(const events::FrameTracked& e) {
  bool kept = false;  // only a frame kept can push another out
  if (!e.removed_keypoints.empty())
    kept |= rank(most_removed_, static_cast<double>(e.removed_keypoints.size()), e);
  if (e.mask_age > 0) kept |= rank(oldest_mask_, e.mask_age, e);
  if (e.T_wc && e.frame_id % pool_stride_ == 0) {
    pool_.push_back(e.frame_id);
    keep(e);
    kept = true;
    if (pool_.size() > kPool) {  // keep every other one: the pool stays evenly spaced over the run
      pool_stride_ *= 2;
      std::erase_if(pool_, [this](std::uint64_t id) { return id % pool_stride_ != 0; });
    }
  }
  if (kept) forget_unused();
}

void SampleFrameRecorder::on_dense_map(const events::DenseMapUpdated& e) {
  if (!e.repair || e.dynamic_pixels == 0) return;
  if (repairs_.size() == kRepairs && e.dynamic_pixels <= repairs_.back().dynamic_pixels) return;
  const auto at = std::find_if(repairs_.begin(), repairs_.end(),
                               [&e](const Repair& r) { return e.dynamic_pixels > r.dynamic_pixels; });
  repairs_.insert(
      at, Repair{e.timestamp, e.dynamic_pixels, e.filled_pixels, repair_picture(e.keyframe, *e.repair)});
  if (repairs_.size() > kRepairs) repairs_.pop_back();
}

bool SampleFrameRecorder::rank(Ranked& ranked, double score, const events::FrameTracked& e) {
  if (ranked.size() == kPerReason && score <= ranked.back().first) return false;
  const auto at =
      std::find_if(ranked.begin(), ranked.end(), [score](const auto& r) { return score > r.first; });
  ranked.insert(at, {score, e.frame_id});
  if (ranked.size() > kPerReason) ranked.pop_back();
  keep(e);
  return true;
}

void SampleFrameRecorder::keep(const events::FrameTracked& e) {
  if (samples_.count(e.frame_id) != 0) return;
  // The event's images are its own buffers: sharing them copies nothing.
  samples_[e.frame_id] =
      Sample{e.frame_id, e.timestamp, e.mask_age,       std::string(tracking::to_string(e.state)),
             e.grey,     e.mask,      e.kept_keypoints, e.removed_keypoints};
}

void SampleFrameRecorder::forget_unused() {
  std::set<std::uint64_t> used(pool_.begin(), pool_.end());
  for (const auto& r : most_removed_) used.insert(r.second);
  for (const auto& r : oldest_mask_) used.insert(r.second);
  std::erase_if(samples_, [&used](const auto& s) { return used.count(s.first) == 0; });
}

void SampleFrameRecorder::write(const fs::path& folder, const io::Trajectory& trajectory,
                                const std::optional<io::Trajectory>& ground_truth,
                                const std::vector<FrameFlags>& flags) const {
  const std::map<double, double> errors = errors_by_stamp(trajectory, ground_truth);
  const auto error_of = [&errors](double t) -> std::optional<double> {
    const auto it = errors.lower_bound(t - 1e-6);
    if (it == errors.end() || it->first > t + 1e-6) return std::nullopt;
    return it->second;
  };
  Ranked largest_error;
  for (const std::uint64_t id : pool_)
    if (const auto err = error_of(samples_.at(id).timestamp)) largest_error.emplace_back(*err, id);
  std::sort(largest_error.begin(), largest_error.end(), std::greater<>());
  if (largest_error.size() > kPerReason) largest_error.resize(kPerReason);

  std::map<std::uint64_t, std::vector<std::string>> reasons;  // by frame: in the page's order
  for (const auto& [score, id] : largest_error) reasons[id].push_back("largest error");
  for (const auto& [score, id] : most_removed_) reasons[id].push_back("most keypoints removed");
  for (const auto& [score, id] : oldest_mask_) reasons[id].push_back("oldest mask");
  fs::create_directories(folder);
  nlohmann::json list = nlohmann::json::array();
  for (const auto& [id, why] : reasons) {
    const Sample& s = samples_.at(id);
    const std::string name = fmt::format("frame_{:06d}.jpg", id);
    write_jpeg(folder / name, draw(s.grey, s.mask, s.kept, s.removed));
    const std::optional<double> err = error_of(s.timestamp);
    list.push_back({{"frame", id},
                    {"timestamp", s.timestamp},
                    {"file", name},
                    {"reasons", why},
                    {"state", s.state},
                    {"kept", s.kept.size()},
                    {"removed", s.removed.size()},
                    {"mask_age", s.mask_age},
                    {"error", err ? nlohmann::json(*err) : nlohmann::json(nullptr)}});
  }
  nlohmann::json repairs = nlohmann::json::array();
  for (std::size_t i = 0; i < repairs_.size(); ++i) {
    const Repair& r = repairs_[i];
    const std::string name = fmt::format("repair_{}.jpg", i);
    write_jpeg(folder / name, r.picture);
    repairs.push_back({{"timestamp", r.timestamp},
                       {"file", name},
                       {"dynamic_pixels", r.dynamic_pixels},
                       {"filled_pixels", r.filled_pixels}});
  }
  // Y on this run's frames (the pool), timed after the run so that nothing competes with it.
  std::vector<cv::Mat> grey;
  for (const std::uint64_t id : pool_) grey.push_back(samples_.at(id).grey);
  const nlohmann::json yardstick = {
      {"ms", grey.empty() ? nlohmann::json(nullptr) : nlohmann::json(util::yardstick_ms(grey))},
      {"frames", grey.size()}};
  util::write_file_bytes(
      folder / "frames.json",
      nlohmann::json{
          {"frames", list}, {"repairs", repairs}, {"yardstick", yardstick}, {"flags", flags_json(flags)}}
              .dump(1) +
          "\n");
}

}  // namespace lrd::runner

namespace lrd::runner {

void write_sparse_map_ply(const std::filesystem::path& file, const events::MapSnapshot& map) {
  dense::PointCloud cloud;
  cloud.points.reserve(map.points.size());
  for (const events::MapPointSnapshot& p : map.points) cloud.points.push_back(p.position.cast<float>());
  dense::write_ply(file, cloud);
}

}  // namespace lrd::runner
