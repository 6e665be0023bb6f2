#include "lrd/runner/dense_evaluation.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "lrd/io/image_file.h"
#include "lrd/util/error.h"

namespace lrd::runner {

namespace fs = std::filesystem;

namespace {
long long micros(double t) {
  return std::llround(t * 1e6);
}

// Five images a keyframe, made again by a rerun: not synced one by one (util::Sync).
void write_png(const fs::path& file, const cv::Mat& img) {
  io::write_image_file(file, img, {}, util::Sync::no);
}

cv::Mat depth_png(const cv::Mat& metres, double factor) {
  cv::Mat out;
  metres.convertTo(out, CV_16U, factor);
  return out;
}
}  // namespace

RepairRecorder::RepairRecorder(const io::FrameSource& sequence, const camera::PinholeCamera& camera,
                               std::optional<fs::path> save_dir)
    : sequence_(sequence),
      depth_factor_(camera.depth_map_factor),
      undistorter_(camera),
      save_dir_(std::move(save_dir)) {
  has_truth_ = sequence.folder() && fs::is_directory(*sequence.folder() / "static" / "depth");
  for (std::size_t i = 0; i < sequence.size(); ++i) by_stamp_[micros(sequence.entry(i).timestamp)] = i;
  if (save_dir_) {
    std::error_code ec;
    fs::create_directories(*save_dir_, ec);
    if (ec) throw file_error(*save_dir_, "cannot create the folder: " + ec.message());
  }
}

void RepairRecorder::record(double timestamp, const dense::RgbdView& keyframe,
                            const dense::RepairResult& repair) {
  const auto it = by_stamp_.find(micros(timestamp));
  if (it == by_stamp_.end()) return;
  const io::FrameEntry& e = sequence_.entry(it->second);
  if (save_dir_) {
    // Originals and repaired images side by side, named by the colour image (like Fig. 12).
    const std::string stem = e.rgb_path.stem().string();
    write_png(*save_dir_ / (stem + "_rgb.png"), keyframe.bgr);
    write_png(*save_dir_ / (stem + "_rgb_repaired.png"), repair.bgr);
    write_png(*save_dir_ / (stem + "_depth.png"), depth_png(keyframe.depth, depth_factor_));
    write_png(*save_dir_ / (stem + "_depth_repaired.png"), depth_png(repair.depth, depth_factor_));
    write_png(*save_dir_ / (stem + "_mask.png"), keyframe.dynamic);
  }
  if (!has_truth_) return;
  Filled f;
  f.truth = *sequence_.folder() / "static" / "depth" / e.depth_path.filename();
  for (int v = 0; v < repair.filled.rows; ++v)
    for (int u = 0; u < repair.filled.cols; ++u)
      if (repair.filled.at<unsigned char>(v, u) != 0) {
        f.pixels.push_back(v * repair.filled.cols + u);
        f.depths.push_back(repair.depth.at<float>(v, u));
      }
  std::lock_guard lock(mutex_);
  filled_.push_back(std::move(f));
}

RepairRecorder::DepthError RepairRecorder::depth_error() const {
  std::lock_guard lock(mutex_);
  std::vector<float> errors;
  for (const Filled& f : filled_) {
    cv::Mat truth = cv::imread(f.truth.string(), cv::IMREAD_UNCHANGED);
    if (truth.empty() || truth.type() != CV_16UC1) continue;
    try {
      truth = undistorter_.nearest(truth);
    } catch (const Error&) {
      continue;  // not the camera's size: nothing to compare
    }
    for (std::size_t i = 0; i < f.pixels.size(); ++i) {
      if (f.pixels[i] >= static_cast<int>(truth.total())) break;
      const std::uint16_t raw = truth.at<std::uint16_t>(f.pixels[i]);
      if (raw != 0) errors.push_back(std::abs(f.depths[i] - static_cast<float>(raw / depth_factor_)));
    }
  }
  DepthError d;
  d.pixels = errors.size();
  if (!errors.empty()) {
    std::nth_element(errors.begin(), errors.begin() + static_cast<long>(errors.size() / 2), errors.end());
    d.median = errors[errors.size() / 2];
  }
  return d;
}

}  // namespace lrd::runner
