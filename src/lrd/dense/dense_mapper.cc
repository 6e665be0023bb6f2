#include "lrd/dense/dense_mapper.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "lrd/dense/confirmation_mask.h"
#include "lrd/dense/voxel_grid.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/map.h"
#include "lrd/util/fault_injection.h"
#include "lrd/util/thread_priority.h"

namespace lrd::dense {

namespace {
constexpr int kCoarse = 4;  // the free-space check's views are 1/4 of the resolution

void append(PointCloud& cloud, const PointCloud& more) {
  cloud.points.insert(cloud.points.end(), more.points.begin(), more.points.end());
  cloud.colours.insert(cloud.colours.end(), more.colours.begin(), more.colours.end());
}
}  // namespace

DenseMapper::DenseMapper(map::Map& map, const camera::PinholeCamera& camera, const DenseParams& params,
                         bool threaded)
    : map_(map),
      camera_(camera),
      coarse_camera_(coarse_camera(camera, kCoarse)),
      undistorter_(camera),
      params_(params),
      repairer_(camera, params.repair) {
  storage_.max_memory_mb = params.max_memory_mb;
  if (threaded) thread_ = std::thread([this] { run(); });
}

DenseMapper::~DenseMapper() {
  try {
    shutdown();
  } catch (const std::exception& e) {
    spdlog::error("dense mapping: {}", e.what());
  } catch (...) {
  }
}

void DenseMapper::add_keyframe(const map::KeyFrame* kf, cv::Mat bgr, cv::Mat depth, cv::Mat dynamic,
                               bool mask_carried) {
  {
    std::lock_guard lock(queue_mutex_);
    if (error_) return;  // the thread stopped at an error; shutdown() reports it
    queue_.push_back({kf->id(),
                      kf->timestamp(),
                      RgbdView{std::move(bgr), std::move(depth), std::move(dynamic), {}},
                      {},
                      mask_carried});
  }
  wake_.notify_one();
}

void DenseMapper::process_queued() {
  for (;;) {
    Pending p;
    {
      std::lock_guard lock(queue_mutex_);
      if (queue_.empty() || error_ || failed_) return;
      p = std::move(queue_.front());
      queue_.pop_front();
    }
    try {
      process(std::move(p));
    } catch (...) {
      // Lock-step: the caller gets the error now; nothing more is processed, shutdown() is quiet.
      std::lock_guard lock(queue_mutex_);
      queue_.clear();
      failed_ = true;
      throw;
    }
  }
}

void DenseMapper::shutdown() {
  if (thread_.joinable()) {
    {
      std::lock_guard lock(queue_mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
  }
  std::exception_ptr error;
  {
    std::lock_guard lock(queue_mutex_);
    std::swap(error, error_);
    if (error) queue_.clear();
  }
  if (error) std::rethrow_exception(error);
  process_queued();  // whatever arrived after the thread stopped, or everything when unthreaded
}

void DenseMapper::run() {
  util::name_this_thread("lrd-dense");
  // Below tracking's priority: on a busy machine the map waits, the camera does not (Linux
  // per-thread nice value; harmless where it is refused).
  if (!util::lower_this_thread_priority())
    spdlog::debug("dense mapping: could not lower the thread priority");
  std::unique_lock lock(queue_mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
    if (queue_.empty()) {
      if (stop_) return;
      continue;
    }
    Pending p = std::move(queue_.front());
    queue_.pop_front();
    lock.unlock();
    try {
      process(std::move(p));
    } catch (...) {
      // Kept for shutdown() to rethrow in the caller's thread; nothing more is processed.
      if (errors_ != nullptr) errors_->capture("dense mapping");
      lock.lock();
      error_ = std::current_exception();
      queue_.clear();
      return;
    }
    lock.lock();
  }
}

void DenseMapper::process(Pending p) {
  util::check_fault_point("dense");
  // Everything below is pinhole: a distorted keyframe is resampled once, here on the dense thread.
  if (undistorter_.active()) {
    p.view.bgr = undistorter_.smooth(p.view.bgr);
    p.view.depth = undistorter_.nearest(p.view.depth);
    p.view.dynamic = undistorter_.nearest(p.view.dynamic);
  }
  // Current poses of this keyframe and of the repair sources (local BA may have moved them since).
  {
    std::lock_guard lock(map_.mutex());
    p.view.T_cw = map_.resolve_pose(p.keyframe_id);
    for (Pending& r : recent_) r.coarse.T_cw = r.view.T_cw = map_.resolve_pose(r.keyframe_id);
  }
  RgbdView repaired_view = p.view;
  std::optional<RepairResult> repair;
  const bool has_dynamic = !p.view.dynamic.empty() && cv::countNonZero(p.view.dynamic) > 0;
  if (params_.repair.enabled && has_dynamic) {
    // The newest repair.keyframes of the kept keyframes.
    std::vector<const RgbdView*> sources;
    const std::size_t first =
        recent_.size() - std::min<std::size_t>(recent_.size(), params_.repair.keyframes);
    for (std::size_t k = first; k < recent_.size(); ++k) sources.push_back(&recent_[k].view);
    const RepairResult& rep = repair.emplace(repairer_.repair(p.view, sources));
    if (on_repair_) on_repair_(p.timestamp, p.view, rep);
    repaired_view.bgr = rep.bgr;
    repaired_view.depth = rep.depth;
    std::lock_guard lock(mutex_);
    ++totals_.keyframes;
    totals_.dynamic_pixels += static_cast<std::size_t>(rep.dynamic_pixels);
    totals_.filled_pixels += static_cast<std::size_t>(rep.filled_pixels);
  }
  // The keyframe's own measurements (its dynamic pixels left out), those it can trust first, then
  // those awaiting a second keyframe's confirmation, then what the repair filled in from earlier
  // keyframes: the occupancy map weighs them in that order.
  const cv::Mat waits = awaiting_confirmation(p.view.dynamic, p.view.depth.size(), params_, p.mask_carried);
  PointCloud local = keyframe_cloud(p.view, waits);
  const std::size_t trusted = local.size();
  cv::Mat not_waiting;  // every pixel but the non-dynamic ones that wait (written, not aliasing `waits`)
  if (p.view.dynamic.empty()) {
    cv::bitwise_not(waits, not_waiting);
  } else {
    cv::bitwise_and(waits, p.view.dynamic == 0, not_waiting);
    cv::bitwise_not(not_waiting, not_waiting);
  }
  append(local, keyframe_cloud(p.view, not_waiting));
  const std::size_t measured = local.size();
  if (repair) {
    cv::Mat not_filled;  // every pixel but the dynamic ones the repair filled
    cv::bitwise_and(p.view.dynamic, repair->filled, not_filled);
    cv::bitwise_not(not_filled, not_filled);
    append(local, keyframe_cloud(repaired_view, not_filled));
  }
  std::vector<std::uint8_t> votes(local.size(), 0);
  const FreeSpaceParams& fs = params_.free_space;
  p.coarse = coarse_view(p.view, kCoarse);
  if (fs.votes > 0) {
    // The new cloud against the recent keyframes, and their clouds against the new keyframe.
    // Only this thread writes stored_ clouds and votes; the votes of earlier clouds are counted
    // into copies and swapped in under the lock, so cloud() never waits for the projections.
    // The latest fs.keyframes keyframes, every fs.step-th counted back from the newest.
    // stored_ ends with recent_'s keyframes, in the same order.
    const std::size_t n = std::min({recent_.size(), stored_.size(), static_cast<std::size_t>(fs.keyframes)});
    std::vector<std::size_t> back;  // 1 = the newest
    for (std::size_t k = 1; k <= n; k += static_cast<std::size_t>(fs.step)) back.push_back(k);
    for (std::size_t k : back)
      vote_free_space(local, p.view.T_cw, recent_[recent_.size() - k].coarse, coarse_camera_, fs, votes);
    std::vector<std::vector<std::uint8_t>> updated(back.size());
    for (std::size_t j = 0; j < back.size(); ++j) {
      const Stored& s = stored_[stored_.size() - back[j]];
      updated[j] = s.votes;
      vote_free_space(*s.local, recent_[recent_.size() - back[j]].view.T_cw, p.coarse, coarse_camera_, fs,
                      updated[j]);
    }
    std::lock_guard lock(mutex_);
    for (std::size_t j = 0; j < back.size(); ++j) stored_[stored_.size() - back[j]].votes.swap(updated[j]);
  }
  std::size_t keyframes = 0;
  {
    std::lock_guard lock(mutex_);
    storage_.points += local.size();
    storage_.bytes += local.size() * kBytesPerPoint;
    stored_.push_back({p.keyframe_id, std::make_shared<const PointCloud>(std::move(local)), std::move(votes),
                       p.timestamp, trusted, measured});
    keyframes = storage_.keyframes = stored_.size();
  }
  if (on_update_) on_update_(p.timestamp, keyframes, p.view, repair ? &*repair : nullptr);
  // The sources are the original images (a repaired pixel is another keyframe's, not a new view).
  recent_.push_back(std::move(p));
  const auto keep =
      static_cast<std::size_t>(std::max(params_.repair.keyframes, params_.free_space.keyframes));
  while (recent_.size() > keep) recent_.pop_front();
  enforce_memory_cap();
}

PointCloud DenseMapper::keyframe_cloud(const RgbdView& view, const cv::Mat& exclude) const {
  VoxelGrid grid(params_.voxel_size);
  const int step = params_.pixel_stride;
  const double fx = camera_.fx, fy = camera_.fy, cx = camera_.cx, cy = camera_.cy;
  for (int v = 0; v < view.depth.rows; v += step) {
    const float* zrow = view.depth.ptr<float>(v);
    const unsigned char* xrow = exclude.empty() ? nullptr : exclude.ptr<unsigned char>(v);
    const cv::Vec3b* crow = view.bgr.ptr<cv::Vec3b>(v);
    for (int u = 0; u < view.depth.cols; u += step) {
      const float z = zrow[u];
      if (!(z > 0.0f && z <= params_.max_depth) || (xrow != nullptr && xrow[u] != 0)) continue;  // NaN too
      if (on_depth_edge(view.depth, u, v, params_.depth_edge)) continue;
      grid.add(
          Eigen::Vector3f(static_cast<float>((u - cx) * z / fx), static_cast<float>((v - cy) * z / fy), z),
          crow[u]);
    }
  }
  return grid.cloud();
}

std::vector<DenseMapper::KeyframeCloud> DenseMapper::keyframe_clouds() const {
  // Under mutex_: which clouds there are, and their votes (the clouds themselves never change).
  std::vector<KeyframeCloud> out;
  const int min_votes = params_.free_space.votes;
  {
    std::lock_guard lock(mutex_);
    out.reserve(stored_.size());
    for (const Stored& s : stored_) {
      KeyframeCloud c;
      c.keyframe_id = s.keyframe_id;
      c.timestamp = s.timestamp;
      c.local = s.local;
      c.trusted = s.trusted;
      c.measured = s.measured;
      c.kept.resize(s.votes.size());
      for (std::size_t k = 0; k < s.votes.size(); ++k) c.kept[k] = min_votes == 0 || s.votes[k] < min_votes;
      out.push_back(std::move(c));
    }
  }
  std::lock_guard map_lock(map_.mutex());
  for (KeyframeCloud& c : out) c.T_wc = map_.resolve_pose(c.keyframe_id).inverse();
  return out;
}

PointCloud DenseMapper::cloud() const {
  const std::vector<KeyframeCloud> parts = keyframe_clouds();
  VoxelGrid grid(params_.voxel_size);
  std::size_t total = 0;
  for (const KeyframeCloud& part : parts) total += part.local->size();
  grid.reserve(total / 2);
  for (const KeyframeCloud& part : parts) {
    const Eigen::Isometry3f T = part.T_wc.cast<float>();
    const PointCloud& c = *part.local;
    for (std::size_t k = 0; k < c.size(); ++k)
      if (part.kept[k]) grid.add(T * c.points[k], c.colours[k]);
  }
  return grid.cloud();
}

RepairTotals DenseMapper::repair_totals() const {
  std::lock_guard lock(mutex_);
  return totals_;
}

DenseStorage DenseMapper::storage() const {
  std::lock_guard lock(mutex_);
  return storage_;
}

}  // namespace lrd::dense
