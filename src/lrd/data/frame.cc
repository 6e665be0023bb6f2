#include "lrd/data/frame.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "lrd/place/vocabulary.h"
#include "lrd/util/error.h"

namespace lrd::data {

Frame::Frame(std::uint64_t id, double timestamp, const cv::Mat& grey, const cv::Mat& depth,
             const cv::Mat& mask, features::OrbExtractor& extractor,
             const features::KeypointUndistorter& undistorter, const camera::PinholeCamera& camera,
             Extraction extraction)
    : id_(id),
      timestamp_(timestamp),
      camera_(camera),
      close_depth_(static_cast<float>(camera.close_depth_threshold())) {
  if (grey.type() != CV_8UC1) throw Error("frame: expected an 8-bit grey image");
  if (depth.type() != CV_32FC1 || depth.size() != grey.size())
    throw Error("frame: expected a CV_32FC1 depth image of the grey image's size");
  if (extraction == Extraction::Full)
    extractor.extract(grey, mask, keypoints_, descriptors_);
  else
    extractor.describe_detected(mask, keypoints_, descriptors_);
  dynamic_mask = mask;
  undistorted_ = undistorter.undistort(keypoints_);
  level_sigma2_ = extractor.level_sigma2();
  inv_level_sigma2_ = extractor.inv_level_sigma2();
  scale_factors_ = extractor.scale_factors();

  // Depth is read at the detected (distorted) pixel: depth is registered to the raw image.
  const std::size_t n = keypoints_.size();
  depth_.assign(n, -1.0f);
  u_right_.assign(n, -1.0f);
  for (std::size_t i = 0; i < n; ++i) {
    const int u = static_cast<int>(std::lround(keypoints_[i].pt.x));
    const int v = static_cast<int>(std::lround(keypoints_[i].pt.y));
    if (u < 0 || v < 0 || u >= depth.cols || v >= depth.rows) continue;
    const float d = depth.at<float>(v, u);
    if (d > 0.0f) {
      depth_[i] = d;
      u_right_[i] = undistorted_[i].pt.x - static_cast<float>(camera.bf) / d;
    }
  }

  map_points.assign(n, nullptr);
  outliers.assign(n, false);

  bounds_ = undistorter.undistorted_bounds();
  cell_w_inv_ = static_cast<float>(kGridCols) / bounds_.width;
  cell_h_inv_ = static_cast<float>(kGridRows) / bounds_.height;
  build_grid();
}

Frame::Frame(std::uint64_t id, double timestamp, const camera::PinholeCamera& camera, SavedFeatures features,
             const Eigen::Isometry3d& T_cw)
    : id_(id),
      timestamp_(timestamp),
      camera_(camera),
      keypoints_(std::move(features.keypoints)),
      undistorted_(std::move(features.undistorted)),
      descriptors_(std::move(features.descriptors)),
      depth_(std::move(features.depth)),
      u_right_(std::move(features.u_right)),
      close_depth_(static_cast<float>(camera.close_depth_threshold())),
      level_sigma2_(std::move(features.level_sigma2)),
      inv_level_sigma2_(std::move(features.inv_level_sigma2)),
      scale_factors_(std::move(features.scale_factors)),
      bounds_(features.bounds) {
  const std::size_t n = keypoints_.size();
  if (undistorted_.size() != n || depth_.size() != n || u_right_.size() != n ||
      static_cast<std::size_t>(descriptors_.rows) != n || (n > 0 && descriptors_.cols != 32))
    throw Error("frame " + std::to_string(id) + ": keypoints, descriptors and depths differ in number");
  if (scale_factors_.empty() || level_sigma2_.size() != scale_factors_.size() ||
      inv_level_sigma2_.size() != scale_factors_.size())
    throw Error("frame " + std::to_string(id) + ": bad pyramid scales");
  for (const cv::KeyPoint& kp : keypoints_)
    if (kp.octave < 0 || static_cast<std::size_t>(kp.octave) >= scale_factors_.size())
      throw Error("frame " + std::to_string(id) + ": a keypoint's level is outside the pyramid");
  if (!(bounds_.width > 0.0f && bounds_.height > 0.0f))
    throw Error("frame " + std::to_string(id) + ": empty image bounds");
  map_points.assign(n, nullptr);
  outliers.assign(n, false);
  cell_w_inv_ = static_cast<float>(kGridCols) / bounds_.width;
  cell_h_inv_ = static_cast<float>(kGridRows) / bounds_.height;
  build_grid();
  T_cw_ = T_cw;  // as saved (already orthonormal): a loaded map saves to the same bytes
}

Frame::SavedFeatures Frame::saved_features() const {
  return {keypoints_,    undistorted_,      descriptors_,   depth_, u_right_,
          level_sigma2_, inv_level_sigma2_, scale_factors_, bounds_};
}

void Frame::compute_bow(const place::Vocabulary& vocabulary) {
  if (bow.empty()) set_words(words(vocabulary));
}

Frame::Words Frame::words(const place::Vocabulary& vocabulary) const {
  Words w;
  vocabulary.transform(descriptors_, w.bow, w.features, kBowLevelsUp);
  return w;
}

void Frame::set_words(Words words) {
  if (!bow.empty()) return;
  bow = std::move(words.bow);
  bow_features = std::move(words.features);
}

void Frame::remove_keypoints(const std::vector<bool>& drop) {
  const std::size_t n = keypoints_.size();
  if (drop.size() != n) throw Error("frame: remove_keypoints needs one flag per keypoint");
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (drop[i]) {
      removed_keypoints.push_back(keypoints_[i]);
      continue;
    }
    if (kept != i) {
      keypoints_[kept] = keypoints_[i];
      undistorted_[kept] = undistorted_[i];
      descriptors_.row(static_cast<int>(i)).copyTo(descriptors_.row(static_cast<int>(kept)));
      depth_[kept] = depth_[i];
      u_right_[kept] = u_right_[i];
      map_points[kept] = map_points[i];
      outliers[kept] = outliers[i];
    }
    ++kept;
  }
  if (kept == n) return;
  keypoints_.resize(kept);
  undistorted_.resize(kept);
  descriptors_ = descriptors_.rowRange(0, static_cast<int>(kept)).clone();
  depth_.resize(kept);
  u_right_.resize(kept);
  map_points.resize(kept);
  outliers.resize(kept);
  // Keypoint indices changed: the direct index no longer fits.
  bow.clear();
  bow_features.clear();
  build_grid();
}

void Frame::move_keypoints(const std::vector<cv::Point2f>& undistorted, const std::vector<float>& depth) {
  const std::size_t n = keypoints_.size();
  if (undistorted.size() != n || depth.size() != n)
    throw Error("frame: move_keypoints needs one position and one depth per keypoint");
  for (std::size_t i = 0; i < n; ++i) {
    undistorted_[i].pt = undistorted[i];
    depth_[i] = depth[i] > 0.0f ? depth[i] : -1.0f;
    u_right_[i] = depth[i] > 0.0f ? undistorted[i].x - static_cast<float>(camera_.bf) / depth[i] : -1.0f;
  }
  build_grid();
}

void Frame::build_grid() {
  // Compressed rows (a counting sort): cell k's keypoints are grid_index_[grid_start_[k] ..
  // grid_start_[k + 1]), in keypoint order. A vector per cell would cost 74 KB of empty vector
  // headers in every keyframe the map keeps.
  const std::size_t n = keypoints_.size();
  constexpr auto kCells = static_cast<std::size_t>(kGridCols * kGridRows);
  std::vector<std::uint32_t> cell_of(n, UINT32_MAX);
  grid_start_.assign(kCells + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    int c, r;
    if (!grid_cell(undistorted_[i].pt, c, r)) continue;
    cell_of[i] = static_cast<std::uint32_t>(r * kGridCols + c);
    ++grid_start_[cell_of[i] + 1];
  }
  for (std::size_t k = 0; k < kCells; ++k) grid_start_[k + 1] += grid_start_[k];
  grid_index_.assign(grid_start_[kCells], 0);
  std::vector<std::uint32_t> next(grid_start_.begin(), grid_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    if (cell_of[i] != UINT32_MAX) grid_index_[next[cell_of[i]]++] = static_cast<std::uint32_t>(i);
}

bool Frame::grid_cell(const cv::Point2f& p, int& col, int& row) const {
  // Compared as floats before the conversion: a point far outside (or NaN, as a corrupt map file
  // may hold) has no int value.
  const float c = std::floor((p.x - bounds_.x) * cell_w_inv_),
              r = std::floor((p.y - bounds_.y) * cell_h_inv_);
  if (!(c >= 0.0f && c < static_cast<float>(kGridCols) && r >= 0.0f && r < static_cast<float>(kGridRows))) {
    col = row = -1;
    return false;
  }
  col = static_cast<int>(c);
  row = static_cast<int>(r);
  return true;
}

std::vector<std::size_t> Frame::features_in_area(float x, float y, float radius, int min_level,
                                                 int max_level) const {
  std::vector<std::size_t> out;
  features_in_area(x, y, radius, min_level, max_level, out);
  return out;
}

void Frame::features_in_area(float x, float y, float radius, int min_level, int max_level,
                             std::vector<std::size_t>& out) const {
  out.clear();
  const int c0 = std::max(0, static_cast<int>(std::floor((x - radius - bounds_.x) * cell_w_inv_)));
  const int c1 =
      std::min(kGridCols - 1, static_cast<int>(std::floor((x + radius - bounds_.x) * cell_w_inv_)));
  const int r0 = std::max(0, static_cast<int>(std::floor((y - radius - bounds_.y) * cell_h_inv_)));
  const int r1 =
      std::min(kGridRows - 1, static_cast<int>(std::floor((y + radius - bounds_.y) * cell_h_inv_)));
  for (int r = r0; r <= r1; ++r) {
    for (int c = c0; c <= c1; ++c) {
      const auto cell = static_cast<std::size_t>(r * kGridCols + c);
      for (std::uint32_t k = grid_start_[cell]; k < grid_start_[cell + 1]; ++k) {
        const std::uint32_t i = grid_index_[k];
        const cv::KeyPoint& kp = undistorted_[i];
        if ((min_level >= 0 && kp.octave < min_level) || (max_level >= 0 && kp.octave > max_level)) continue;
        if (std::abs(kp.pt.x - x) <= radius && std::abs(kp.pt.y - y) <= radius) out.push_back(i);
      }
    }
  }
  std::sort(out.begin(), out.end());  // deterministic order whatever the grid traversal
}

std::optional<Eigen::Vector3d> Frame::unproject_world(std::size_t i) const {
  if (!T_cw_ || depth_[i] <= 0.0f) return std::nullopt;
  const cv::Point2f& p = undistorted_[i].pt;
  return T_cw_->inverse() * camera_.unproject(p.x, p.y, depth_[i]);
}

namespace {
template <class T>
std::size_t vector_bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}
std::size_t mat_bytes(const cv::Mat& m) {
  return m.empty() ? 0 : m.total() * m.elemSize();
}
// A node of std::map: the value, three links and the colour, rounded as the allocator does.
template <class Map>
std::size_t map_bytes(const Map& m) {
  return m.size() * (sizeof(typename Map::value_type) + 4 * sizeof(void*));
}
}  // namespace

std::size_t Frame::memory_bytes() const {
  std::size_t bytes = vector_bytes(keypoints_) + vector_bytes(undistorted_) + mat_bytes(descriptors_) +
                      vector_bytes(depth_) + vector_bytes(u_right_) + vector_bytes(level_sigma2_) +
                      vector_bytes(inv_level_sigma2_) + vector_bytes(scale_factors_) +
                      vector_bytes(grid_start_) + vector_bytes(grid_index_) + vector_bytes(map_points) +
                      outliers.capacity() / 8 + mat_bytes(dynamic_mask) + vector_bytes(removed_keypoints) +
                      map_bytes(bow) + map_bytes(bow_features);
  for (const auto& [node, indices] : bow_features) bytes += vector_bytes(indices);
  return bytes;
}

}  // namespace lrd::data
