#include "lrd/runner/dense_evaluation.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "lrd/dense/ply_io.h"
#include "lrd/eval/ate.h"
#include "lrd/util/error.h"

namespace lrd::runner {

namespace fs = std::filesystem;

namespace {
long long micros(double t) {
  return std::llround(t * 1e6);
}

void write_png(const fs::path& file, const cv::Mat& img) {
  if (!cv::imwrite(file.string(), img)) throw file_error(file, "cannot write");
}

cv::Mat depth_png(const cv::Mat& metres, double factor) {
  cv::Mat out;
  metres.convertTo(out, CV_16U, factor);
  return out;
}
}  // namespace

RepairRecorder::RepairRecorder(const io::FrameSource& sequence, double depth_factor,
                               std::optional<fs::path> save_dir)
    : sequence_(sequence), depth_factor_(depth_factor), save_dir_(std::move(save_dir)) {
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
    const cv::Mat truth = cv::imread(f.truth.string(), cv::IMREAD_UNCHANGED);
    if (truth.empty() || truth.type() != CV_16UC1) continue;
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

eval::MapAccuracy evaluate_dense_map(const dense::PointCloud& map, const io::Trajectory& estimate,
                                     const fs::path& sequence, const camera::PinholeCamera& camera,
                                     double max_depth, double threshold, int frame_stride) {
  const fs::path scene_file = sequence / "scene.ply";
  if (!fs::exists(scene_file)) throw file_error(scene_file, "no scene model to judge the dense map against");
  const io::TumSequence seq = io::TumSequence::open(sequence);
  if (!seq.groundtruth_path()) throw file_error(sequence, "no groundtruth.txt to align the map with");
  const io::Trajectory gt = io::read_trajectory_tum(*seq.groundtruth_path());
  eval::AteResult ate;
  try {
    ate = eval::compute_ate(gt, estimate);
  } catch (const Error& e) {
    throw file_error(*seq.groundtruth_path(),
                     std::string("cannot align the map's trajectory with it: ") + e.what());
  }
  const dense::PointCloud scene = dense::read_ply(scene_file);

  // The map goes onto the ground truth by the rigid transform that best maps the estimated
  // camera poses onto the true ones — rotations and positions, not positions alone as ATE does:
  // a camera that hardly moves (walking_static) leaves the rotation of a position-only fit
  // undetermined, and the whole map would be judged tilted.
  Eigen::Matrix3d rotations = Eigen::Matrix3d::Zero();
  for (const eval::Match& m : ate.matches)
    rotations += gt[m.first].pose.linear() * estimate[m.second].pose.linear().transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(rotations, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) S(2, 2) = -1.0;
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();
  alignment.linear() = svd.matrixU() * S * svd.matrixV().transpose();
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  for (const eval::Match& m : ate.matches)
    offset += gt[m.first].pose.translation() - alignment.linear() * estimate[m.second].pose.translation();
  alignment.translation() = offset / static_cast<double>(ate.matches.size());

  std::vector<Eigen::Vector3f> aligned(map.size());
  const Eigen::Isometry3f A = alignment.cast<float>();
  for (std::size_t i = 0; i < map.size(); ++i) aligned[i] = A * map.points[i];

  // Ground-truth views: poses by timestamp from groundtruth.txt (synthetic: one per frame).
  std::unordered_map<long long, Eigen::Isometry3d> gt_pose;
  for (const io::StampedPose& p : gt) gt_pose[micros(p.timestamp)] = p.pose;
  std::vector<eval::TruthView> views;
  for (std::size_t i = 0; i < seq.size(); i += static_cast<std::size_t>(std::max(1, frame_stride))) {
    const auto it = gt_pose.find(micros(seq.entry(i).timestamp));
    if (it == gt_pose.end()) continue;
    eval::TruthView v;
    v.T_cw = it->second.inverse();
    v.depth = seq.load_rgbd(i, camera.depth_map_factor).depth;
    const fs::path mask_file = sequence / "mask" / seq.entry(i).rgb_path.filename();
    if (fs::exists(mask_file)) {
      v.dynamic = cv::imread(mask_file.string(), cv::IMREAD_UNCHANGED);
      if (v.dynamic.type() != CV_8UC1 || v.dynamic.size() != v.depth.size())
        throw file_error(mask_file, "mask must be an 8-bit single-channel PNG of the depth image's size");
    }
    views.push_back(std::move(v));
  }
  if (views.empty())
    throw file_error(*seq.groundtruth_path(), "no ground-truth pose at any frame's timestamp");
  const std::vector<char> seen = eval::seen_samples(scene.points, camera, views, max_depth);
  return eval::evaluate_map(aligned, scene.points, seen, threshold);
}

}  // namespace lrd::runner
