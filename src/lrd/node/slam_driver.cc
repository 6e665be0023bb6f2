#include "lrd/node/slam_driver.h"

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "lrd/util/binary_io.h"
#include "lrd/util/yardstick.h"

namespace lrd::node {

namespace fs = std::filesystem;

namespace {
constexpr const char* kNoFrames = "no frames tracked yet";
}  // namespace

SlamDriver::SlamDriver(NodeParams params, std::shared_ptr<TopicPublisher> publisher, NodeLog log,
                       std::function<void()> on_fatal)
    : params_(std::move(params)),
      // Read once: an unreadable config stops the node now, not at the first frame.
      names_camera_(names_camera(params_.system)),
      publisher_(std::move(publisher)),
      log_(std::move(log)),
      on_fatal_(std::move(on_fatal)),
      frames_(static_cast<std::size_t>(params_.queue_size)) {
  tracker_ = std::thread([this] { track_frames(); });
}

SlamDriver::~SlamDriver() {
  try {
    stop();
  } catch (const std::exception& e) {
    log_.error(e.what());
  }
}

void SlamDriver::count_received() {
  std::lock_guard lock(counts_mutex_);
  ++counts_.received;
}

void SlamDriver::push(NodeFrame frame) {
  if (frames_.push(std::move(frame))) return;
  // The node is stopping: a pair that arrives now is not taken, so not counted either.
  std::lock_guard lock(counts_mutex_);
  --counts_.received;
}

NodeCounts SlamDriver::counts() const {
  std::lock_guard lock(counts_mutex_);
  NodeCounts c = counts_;
  c.queue_dropped = frames_.dropped();
  return c;
}

void SlamDriver::drop(std::size_t NodeCounts::*counter, const std::string& why) {
  // Throttled per kind, by hand: two threads (the image callback, tracking) come here.
  std::size_t n = 0;
  bool warn = false;
  {
    std::lock_guard lock(counts_mutex_);
    n = ++(counts_.*counter);
    const auto now = std::chrono::steady_clock::now();
    auto last = std::find_if(last_warning_.begin(), last_warning_.end(),
                             [counter](const auto& w) { return w.first == counter; });
    if (last == last_warning_.end()) {
      last_warning_.emplace_back(counter, now);
      warn = true;
    } else if (std::chrono::duration<double>(now - last->second).count() >= params_.warn_period_s) {
      last->second = now;
      warn = true;
    }
  }
  if (warn) log_.warn(fmt::format("dropped a frame ({} so far of this kind): {}", n, why));
}

void SlamDriver::set_camera_info(const io::SourceCamera& camera) {
  std::lock_guard lock(camera_mutex_);
  camera_info_ = camera;
}

bool SlamDriver::start_system(const NodeFrame& first) {
  std::optional<io::SourceCamera> info;
  {
    std::lock_guard lock(camera_mutex_);
    info = camera_info_;
  }
  if (!names_camera_ && !info) {
    drop(&NodeCounts::no_camera, fmt::format("no camera yet: no camera_info on {} and no {}settings",
                                             params_.camera_info_topic, params_.param_prefix));
    return false;
  }
  auto system = std::make_unique<NodeSystem>(make_system(params_.system, info));
  system->system->subscribe(publisher_);
  publisher_->attach(system->system.get(), first.frame_id);
  log_.info(fmt::format("camera from {}; {}", system->camera_source, system->description));
  if (params_.autosave_s > 0.0) {
    fs::create_directories(params_.output_dir);
    // Saves wait for a reset (TopicPublisher::exclusive), as the publishers' reads of the map do.
    autosaver_ = std::make_shared<autosave::Autosaver>(
        *system->system,
        autosave::AutosaveOptions{params_.autosave_s, params_.output_dir / "map.lrdmap",
                                  params_.output_dir / "CameraTrajectory.txt"},
        [this](const std::function<void()>& save) { publisher_->shared(save); });
    system->system->subscribe(autosaver_);
    autosaver_->start();
  }
  std::lock_guard lock(system_mutex_);
  system_ = std::move(system);
  return true;
}

void SlamDriver::track(NodeFrame& f) {
  if (!system_ && !start_system(f)) return;
  System& slam = *system_->system;
  if (reset_requested_.exchange(false)) {
    publisher_->exclusive([&] { slam.reset(); });
    publisher_->publish_path({});
    last_timestamp_ = -1.0;
    log_.info("reset: a new map starts with this frame");
  }
  if (f.timestamp <= last_timestamp_)
    return drop(&NodeCounts::malformed, fmt::format("stamp {:.6f} is not after the previous frame's {:.6f}",
                                                    f.timestamp, last_timestamp_));
  const camera::PinholeCamera& camera = system_->camera;
  if (f.rgb.cols != camera.width || f.rgb.rows != camera.height)
    return drop(&NodeCounts::malformed,
                fmt::format("image is {}x{}, the camera ({}) is {}x{}", f.rgb.cols, f.rgb.rows,
                            system_->camera_source, camera.width, camera.height));
  if (camera.rgb_order) cv::cvtColor(f.rgb, f.rgb, cv::COLOR_BGR2RGB);
  last_timestamp_ = f.timestamp;
  TrackResult r = slam.track_rgbd(f.rgb, f.depth, f.timestamp);
  publisher_->publish_result(f.timestamp, r);
  latencies_ms_.push_back(
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - f.arrival).count());
  r.dynamic.mask.release();
  times_.push_back({times_.size(), f.timestamp, r});
  std::lock_guard lock(counts_mutex_);
  if (r.state == TrackingState::Ok)
    ++counts_.tracked;
  else if (r.state == TrackingState::Lost)
    ++counts_.lost;
  else
    ++counts_.not_initialized;
}

// Frames dropped because tracking is slower than the camera: said every warn period.
void SlamDriver::report_queue_drops(std::chrono::steady_clock::time_point& last_report,
                                    std::size_t& reported) {
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - last_report).count() < params_.warn_period_s) return;
  const std::size_t dropped = frames_.dropped();
  if (dropped > reported)
    log_.warn(
        fmt::format("dropped {} frames in the last {:.0f} s ({} in all): tracking is slower than the camera",
                    dropped - reported, params_.warn_period_s, dropped));
  reported = dropped;
  last_report = now;
}

void SlamDriver::track_frames() {
  auto last_report = std::chrono::steady_clock::now();
  std::size_t reported = 0;
  while (auto f = frames_.pop()) {
    report_queue_drops(last_report, reported);
    try {
      track(*f);
    } catch (const std::exception& e) {
      // A worker thread failed, or settings the node cannot run with: nothing to go on with.
      log_.error(e.what());
      failed_ = true;
      on_fatal_();
      return;
    }
  }
}

bool SlamDriver::save(const fs::path& dir, std::string* message) {
  std::lock_guard lock(system_mutex_);
  if (!system_) {
    *message = kNoFrames;
    return false;
  }
  fs::create_directories(dir);
  io::Trajectory trajectory;
  publisher_->shared([&] {
    trajectory = system_->system->trajectory();
    io::write_trajectory_tum(dir / "CameraTrajectory.txt", trajectory);
    system_->system->save_keyframe_trajectory_tum(dir / "KeyFrameTrajectory.txt");
  });
  publisher_->publish_path(trajectory);  // the last path is the saved trajectory
  *message = fmt::format("{} poses to {}", trajectory.size(), (dir / "CameraTrajectory.txt").string());
  return true;
}

void SlamDriver::save_final_map() {
  try {
    system_->system->save_map(params_.output_dir / "map.lrdmap");
  } catch (const std::exception& e) {
    log_.error(std::string("final map not written (the last autosave stays): ") + e.what());
  }
}

void SlamDriver::save_occupancy(const fs::path& dir) {
  const System& system = *system_->system;
  if (!system.occupancy_enabled()) return;
  // The maps a planner loads next time (map_server), from the final keyframe poses.
  try {
    std::vector<Eigen::Vector3d> path;
    for (const io::StampedPose& p : system.trajectory()) path.push_back(p.pose.translation());
    occupancy::write_occupancy(system.occupancy(), system.occupancy_params(), path, dir);
  } catch (const std::exception& e) {
    log_.error(std::string("occupancy map not written: ") + e.what());
  }
}

namespace {

// The latencies' median, 99th percentile and maximum (nearest rank), ms.
nlohmann::json latency_stats(std::vector<double> ms) {
  if (ms.empty()) return nullptr;
  std::sort(ms.begin(), ms.end());
  const auto rank = [&](double q) {
    return ms[std::min(ms.size() - 1, static_cast<std::size_t>(q * ms.size()))];
  };
  return {{"frames", ms.size()}, {"median", rank(0.5)}, {"p99", rank(0.99)}, {"max", ms.back()}};
}

// Y timed beside the frames (the yardstick parameter), median ms; null without it.
nlohmann::json yardstick_median(const std::vector<FrameTime>& frames) {
  std::vector<double> ms;
  for (const FrameTime& f : frames)
    if (f.result.timing.yardstick > 0.0) ms.push_back(1e3 * f.result.timing.yardstick);
  if (ms.empty()) return nullptr;
  return util::median_of(std::move(ms));
}

}  // namespace

void SlamDriver::write_summary(const NodeCounts& counts, std::size_t loops) const {
  const nlohmann::json summary = {{"received", counts.received},
                                  {"malformed", counts.malformed},
                                  {"queue_dropped", counts.queue_dropped},
                                  {"no_camera", counts.no_camera},
                                  {"tracked", counts.tracked},
                                  {"lost", counts.lost},
                                  {"not_initialized", counts.not_initialized},
                                  {"loops", loops},
                                  {"latency_ms", latency_stats(latencies_ms_)},
                                  {"yardstick_ms", yardstick_median(times_)}};
  util::write_file_bytes(params_.output_dir / "node_summary.json", summary.dump(2) + "\n");
}

void SlamDriver::stop() {
  if (stopped_) return;
  stopped_ = true;
  publisher_->stop_occupancy();  // its thread reads the system, which ends after this
  frames_.close();
  if (tracker_.joinable()) tracker_.join();
  const NodeCounts c = counts();
  std::string saved = "no frames tracked";
  std::size_t loops = 0;
  std::exception_ptr error;            // a worker thread's, rethrown once everything is written
  if (autosaver_) autosaver_->stop();  // before the system's threads end
  if (system_) {
    try {
      system_->system->shutdown();
    } catch (...) {
      error = std::current_exception();
    }
    save(params_.output_dir, &saved);
    if (autosaver_) save_final_map();
    loops = system_->system->map_stats().loops;
    save_occupancy(params_.output_dir);
  }
  fs::create_directories(params_.output_dir);
  write_track_times(params_.output_dir / "track_times.txt", times_);
  write_summary(c, loops);
  log_.info(fmt::format(
      "stopped: {} pairs received, {} tracked, {} lost, dropped {} (tracking behind), {} (malformed), {} (no "
      "camera); {}",
      c.received, c.tracked, c.lost, c.queue_dropped, c.malformed, c.no_camera, saved));
  if (error) std::rethrow_exception(error);
}

}  // namespace lrd::node
