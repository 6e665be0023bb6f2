#include "lrd/runner/map_evaluation.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <optional>

#include "lrd/camera/image_undistorter.h"
#include "lrd/dense/ply_io.h"
#include "lrd/eval/ate.h"
#include "lrd/io/tum_sequence.h"
#include "lrd/util/error.h"

namespace lrd::runner {

namespace fs = std::filesystem;

namespace {
// Two ground-truth samples farther apart than this are a gap in the capture, not interpolated.
constexpr double kMaxGroundTruthGap = 0.05;  // s

Eigen::Isometry3d align_poses(const io::Trajectory& gt, const io::Trajectory& estimate,
                              const std::vector<eval::Match>& matches) {
  Eigen::Matrix3d rotations = Eigen::Matrix3d::Zero();
  for (const eval::Match& m : matches)
    rotations += gt[m.first].pose.linear() * estimate[m.second].pose.linear().transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(rotations, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) S(2, 2) = -1.0;
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();
  alignment.linear() = svd.matrixU() * S * svd.matrixV().transpose();
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  for (const eval::Match& m : matches)
    offset += gt[m.first].pose.translation() - alignment.linear() * estimate[m.second].pose.translation();
  alignment.translation() = offset / static_cast<double>(matches.size());
  return alignment;
}

// The people as a view saw them: its masked pixels' depth (every second pixel), in the world.
void add_people(const eval::TruthView& v, const camera::PinholeCamera& camera, double max_depth,
                std::vector<Eigen::Vector3f>& people) {
  if (v.dynamic.empty()) return;
  const Eigen::Isometry3f T_wc = v.T_cw.inverse().cast<float>();
  for (int y = 0; y < v.depth.rows; y += 2)
    for (int x = 0; x < v.depth.cols; x += 2) {
      const float z = v.depth.at<float>(y, x);
      if (v.dynamic.at<std::uint8_t>(y, x) == 0 || !(z > 0.0f) || z > max_depth) continue;
      people.push_back(T_wc * Eigen::Vector3f(static_cast<float>((x - camera.cx) * z / camera.fx),
                                              static_cast<float>((y - camera.cy) * z / camera.fy), z));
    }
}
}  // namespace

SceneTruth load_scene_truth(const io::Trajectory& estimate, const fs::path& sequence,
                            const camera::PinholeCamera& camera, double max_depth, int frame_stride) {
  const fs::path scene_file = sequence / "scene.ply";
  if (!fs::exists(scene_file)) throw file_error(scene_file, "no scene model to judge the map against");
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
  SceneTruth truth;
  truth.alignment = align_poses(gt, estimate, ate.matches);
  truth.scene = dense::read_ply(scene_file);

  // Ground-truth views: each frame's pose at its image's stamp (synthetic `clean`: a sample per
  // frame; `tum`: 100 Hz motion capture on its own clock, interpolated), its depth and mask
  // resampled to the ideal camera the checks below project with (`tum` renders a lens distortion).
  const camera::ImageUndistorter undistorter(camera);
  std::vector<eval::TruthView> views;
  for (std::size_t i = 0; i < seq.size(); i += static_cast<std::size_t>(std::max(1, frame_stride))) {
    const std::optional<Eigen::Isometry3d> pose = io::pose_at(gt, seq.entry(i).timestamp, kMaxGroundTruthGap);
    if (!pose) continue;
    eval::TruthView v;
    v.T_cw = pose->inverse();
    v.depth = undistorter.nearest(seq.load_rgbd(i, camera.depth_map_factor).depth);
    const fs::path mask_file = sequence / "mask" / seq.entry(i).rgb_path.filename();
    if (fs::exists(mask_file)) {
      v.dynamic = cv::imread(mask_file.string(), cv::IMREAD_UNCHANGED);
      if (v.dynamic.type() != CV_8UC1 || v.dynamic.size() != v.depth.size())
        throw file_error(mask_file, "mask must be an 8-bit single-channel PNG of the depth image's size");
      v.dynamic = undistorter.nearest(v.dynamic);
    }
    add_people(v, camera, max_depth, truth.people);
    views.push_back(std::move(v));
  }
  if (views.empty())
    throw file_error(*seq.groundtruth_path(), "no ground-truth pose at any frame's timestamp");
  truth.seen = eval::seen_samples(truth.scene.points, camera, views, max_depth);
  return truth;
}

eval::MapAccuracy evaluate_dense_map(const dense::PointCloud& map, const SceneTruth& truth,
                                     double threshold) {
  std::vector<Eigen::Vector3f> aligned(map.size());
  const Eigen::Isometry3f A = truth.alignment.cast<float>();
  for (std::size_t i = 0; i < map.size(); ++i) aligned[i] = A * map.points[i];
  return eval::evaluate_map(aligned, truth.scene.points, truth.seen, threshold);
}

eval::OccupancyAccuracy evaluate_occupancy(const occupancy::OccupancyMap& map, const occupancy::Grid2d& grid,
                                           const SceneTruth& truth) {
  const Eigen::Isometry3d& A = truth.alignment;
  std::vector<Eigen::Vector3f> occupied;
  for (const Eigen::Vector3d& v : map.occupied_voxels()) occupied.push_back((A * v).cast<float>());
  // Cell centres at the band's middle height, into the world.
  std::vector<Eigen::Vector3f> cells;
  const double mid = 0.5 * (grid.min_height + grid.max_height);
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x) {
      const Eigen::Vector3d q(grid.origin.x() + (x + 0.5) * grid.resolution,
                              grid.origin.y() + (y + 0.5) * grid.resolution, mid);
      cells.push_back((A * grid.floor.to_map(q)).cast<float>());
    }
  const eval::OccupancyTruth t{truth.scene.points, truth.seen, truth.people, grid.min_height,
                               grid.max_height};
  return eval::evaluate_occupancy(occupied, cells, grid.cells, t, map.resolution());
}

}  // namespace lrd::runner
