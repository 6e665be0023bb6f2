#include "lrd/system.h"

#include <fmt/format.h>

#include <chrono>
#include <limits>
#include <mutex>
#include <opencv2/imgproc.hpp>

#include "lrd/data/frame.h"
#include "lrd/features/keypoint_undistorter.h"
#include "lrd/features/orb_extractor.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/map.h"
#include "lrd/mapping/local_mapper.h"
#include "lrd/tracking/tracker.h"
#include "lrd/util/error.h"

namespace lrd {

namespace {
using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

std::string describe(const cv::Mat& m) {
  return fmt::format("{}x{} {}", m.cols, m.rows, cv::typeToString(m.type()));
}
}  // namespace

struct System::Impl {
  Impl(const config::Config& cfg, SystemOptions opts)
      : config(cfg),
        options(opts),
        extractor(cfg.features),
        undistorter(cfg.camera),
        mapper(map, mapping::LocalMapperParams::from_config(cfg.mapping), !opts.deterministic),
        tracker(map, mapper, tracking::TrackerParams::from_config(cfg.tracking)) {}

  config::Config config;
  SystemOptions options;
  features::OrbExtractor extractor;
  features::KeypointUndistorter undistorter;
  map::Map map;
  mapping::LocalMapper mapper;
  tracking::Tracker tracker;
  std::uint64_t next_frame_id = 0;
  double last_timestamp = -std::numeric_limits<double>::infinity();
  bool shut_down = false;
};

System::System(const config::Config& config, SystemOptions options)
    : impl_(std::make_unique<Impl>(config, options)) {}

System::~System() { shutdown(); }

void System::shutdown() {
  if (impl_->shut_down) return;
  impl_->mapper.shutdown();
  impl_->shut_down = true;
}

const config::Config& System::config() const { return impl_->config; }

TrackingState System::state() const {
  std::lock_guard lock(impl_->map.mutex());
  return impl_->tracker.state();
}

TrackResult System::track_rgbd(const cv::Mat& rgb, const cv::Mat& depth, double timestamp, const cv::Mat& mask) {
  Impl& s = *impl_;
  if (s.shut_down) throw Error("track_rgbd: the system has been shut down");
  const camera::PinholeCamera& cam = s.config.camera;
  if (rgb.empty() || (rgb.type() != CV_8UC3 && rgb.type() != CV_8UC1))
    throw Error(fmt::format("track_rgbd: colour image must be CV_8UC3 or CV_8UC1, got {}", describe(rgb)));
  if (rgb.cols != cam.width || rgb.rows != cam.height)
    throw Error(fmt::format("track_rgbd: colour image is {}x{}, the camera '{}' is {}x{}", rgb.cols, rgb.rows,
                            cam.name, cam.width, cam.height));
  if (depth.size() != rgb.size() || (depth.type() != CV_16UC1 && depth.type() != CV_32FC1))
    throw Error(fmt::format("track_rgbd: depth must be CV_16UC1 or CV_32FC1 of the colour image's size, got {}",
                            describe(depth)));
  if (!mask.empty() && (mask.type() != CV_8UC1 || mask.size() != rgb.size()))
    throw Error(fmt::format("track_rgbd: mask must be CV_8UC1 of the colour image's size, got {}", describe(mask)));
  if (!(timestamp > s.last_timestamp))
    throw Error(fmt::format("track_rgbd: timestamp {:.6f} does not increase (previous {:.6f})", timestamp,
                            s.last_timestamp));
  s.last_timestamp = timestamp;

  TrackResult result;
  const auto t0 = Clock::now();
  cv::Mat grey;
  if (rgb.channels() == 3) cv::cvtColor(rgb, grey, cam.rgb_order ? cv::COLOR_RGB2GRAY : cv::COLOR_BGR2GRAY);
  else grey = rgb;
  cv::Mat depth_m;
  if (depth.type() == CV_16UC1) depth.convertTo(depth_m, CV_32F, 1.0 / cam.depth_map_factor);
  else depth_m = depth;
  data::Frame frame(s.next_frame_id++, timestamp, grey, depth_m, mask, s.extractor, s.undistorter, cam);
  const auto t1 = Clock::now();
  double wait = 0.0;
  result.state = s.tracker.track(frame, &wait);
  const auto t2 = Clock::now();
  if (s.options.deterministic) s.mapper.process_queued();
  const auto t3 = Clock::now();

  result.timing.extraction = seconds(t0, t1);
  result.timing.waiting = wait;
  result.timing.tracking = seconds(t1, t2) - wait;
  result.timing.mapping = seconds(t2, t3);
  result.inliers = s.tracker.records().back().inliers;
  if (result.state == TrackingState::Ok) result.T_wc = frame.T_wc();
  return result;
}

namespace {
// Current world-to-camera pose of a frame recorded relative to `ref`, following the spanning tree
// past keyframes removed since.
Eigen::Isometry3d resolve(const map::KeyFrame* ref, Eigen::Isometry3d T_c_ref) {
  while (ref->is_bad() && ref->parent() != nullptr) {
    T_c_ref = T_c_ref * ref->T_c_parent();
    ref = ref->parent();
  }
  return T_c_ref * ref->T_cw();
}
}  // namespace

io::Trajectory System::trajectory() const {
  std::lock_guard lock(impl_->map.mutex());
  io::Trajectory out;
  for (const tracking::FrameRecord& r : impl_->tracker.records()) {
    if (r.state != TrackingState::Ok || r.reference == nullptr) continue;
    out.push_back({r.timestamp, resolve(r.reference, r.T_c_ref).inverse()});
  }
  return out;
}

io::Trajectory System::keyframe_trajectory() const {
  std::lock_guard lock(impl_->map.mutex());
  io::Trajectory out;
  for (const map::KeyFrame* kf : impl_->map.keyframes()) out.push_back({kf->timestamp(), kf->T_wc()});
  return out;
}

void System::save_trajectory_tum(const std::filesystem::path& file) const { io::write_trajectory_tum(file, trajectory()); }

void System::save_keyframe_trajectory_tum(const std::filesystem::path& file) const {
  io::write_trajectory_tum(file, keyframe_trajectory());
}

MapStats System::map_stats() const {
  MapStats m;
  {
    std::lock_guard lock(impl_->map.mutex());
    m.keyframes = impl_->map.keyframe_count();
    m.map_points = impl_->map.map_point_count();
  }
  const auto ms = impl_->mapper.stats();
  m.culled_keyframes = ms.culled_keyframes;
  m.bundle_adjustments = ms.bundle_adjustments;
  return m;
}

}  // namespace lrd
