#include "lrd/system.h"

#include <fmt/format.h>

#include <chrono>
#include <limits>
#include <map>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

#include "lrd/data/frame.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/map_point.h"
#include "lrd/pipeline.h"
#include "lrd/util/error.h"
#include "lrd/util/project_files.h"

namespace lrd {

namespace {
using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

std::string describe(const cv::Mat& m) { return fmt::format("{}x{} {}", m.cols, m.rows, cv::typeToString(m.type())); }

// Vocabularies are shared between systems of one process (tests and benchmarks build many).
std::shared_ptr<const place::Vocabulary> load_vocabulary(const std::filesystem::path& file) {
  static std::mutex mutex;
  static std::map<std::filesystem::path, std::weak_ptr<const place::Vocabulary>> cache;
  std::lock_guard lock(mutex);
  const std::filesystem::path key = std::filesystem::absolute(file).lexically_normal();
  if (auto v = cache[key].lock()) return v;
  auto v = std::make_shared<const place::Vocabulary>(place::Vocabulary::load(file));
  cache[key] = v;
  return v;
}

constexpr const char* kShippedVocabulary = "vocab/orb_vocab.lrdv";

std::vector<cv::Point2f> points_of(const std::vector<cv::KeyPoint>& keypoints) {
  std::vector<cv::Point2f> out;
  out.reserve(keypoints.size());
  for (const cv::KeyPoint& k : keypoints) out.push_back(k.pt);
  return out;
}
}  // namespace

struct System::Impl {
  Impl(const config::Config& cfg, SystemParams p, SystemOptions opts)
      : config(cfg), params(std::move(p)), options(opts), publisher(errors, opts.max_queued_frame_events) {
    // The shipped vocabulary is optional (a library user may run without it); a configured one
    // must load.
    const std::filesystem::path& configured = params.loop_closing.vocabulary;
    vocabulary_file = configured.empty() ? util::find_project_file(kShippedVocabulary) : configured;
    if (!configured.empty() || std::filesystem::exists(vocabulary_file)) {
      vocabulary = load_vocabulary(vocabulary_file);
    } else {
      spdlog::warn("no vocabulary at {}: no relocalization or loop closing", vocabulary_file.string());
      vocabulary_file.clear();
    }
    start_pipeline();
  }

  void start_pipeline() {
    pipe = std::make_unique<Pipeline>(config, params, options.deterministic, vocabulary.get(), errors, publisher);
    if (repair_callback && pipe->dense) pipe->dense->set_repair_callback(repair_callback);
  }

  TrackResult track(const cv::Mat& rgb, const cv::Mat& depth, double timestamp, const cv::Mat& mask);
  void publish_frame(const TrackResult& r, const tracking::TrackOutcome& outcome, const data::Frame& frame,
                     const cv::Mat& grey, bool grey_shared);

  config::Config config;
  SystemParams params;
  SystemOptions options;
  std::filesystem::path vocabulary_file;
  std::shared_ptr<const place::Vocabulary> vocabulary;
  util::ThreadErrors errors;
  events::EventPublisher publisher;  // before `pipe`: its threads publish until they stop
  dense::DenseMapper::RepairCallback repair_callback;
  std::unique_ptr<Pipeline> pipe;
  std::uint64_t next_frame_id = 0;
  double last_timestamp = -std::numeric_limits<double>::infinity();
  bool shut_down = false;
};

System::System(const config::Config& config, SystemOptions options)
    : System(config, SystemParams::from_config(config, options), options) {}

System::System(const config::Config& config, SystemParams params, SystemOptions options)
    : impl_(std::make_unique<Impl>(config, std::move(params), options)) {}

System::~System() {
  try {
    shutdown();
  } catch (const std::exception& e) {
    spdlog::error("shutdown: {}", e.what());
  }
}

void System::shutdown() {
  if (impl_->shut_down) return;
  impl_->shut_down = true;
  std::exception_ptr stage_error;
  try {
    impl_->pipe->shutdown();
  } catch (...) {
    stage_error = std::current_exception();
  }
  impl_->publisher.shutdown();
  impl_->errors.rethrow();  // a thread's first error comes first
  if (stage_error) std::rethrow_exception(stage_error);
}

void System::reset() {
  Impl& s = *impl_;
  if (s.shut_down) throw Error("reset: the system has been shut down");
  s.pipe->shutdown();
  s.errors.rethrow();
  s.pipe.reset();
  s.start_pipeline();
  s.last_timestamp = -std::numeric_limits<double>::infinity();
}

void System::subscribe(std::shared_ptr<events::Subscriber> subscriber) { impl_->publisher.subscribe(std::move(subscriber)); }

events::PublisherStats System::publisher_stats() const { return impl_->publisher.stats(); }

const config::Config& System::config() const { return impl_->config; }

dynamic::DynamicMode System::mode() const { return impl_->params.dynamic.mode; }

std::string System::segmentation_description() const { return impl_->pipe->front_end.segmentation_description(); }

bool System::dense_enabled() const { return impl_->pipe->dense != nullptr; }

dense::PointCloud System::dense_map() const { return impl_->pipe->dense ? impl_->pipe->dense->cloud() : dense::PointCloud{}; }

dense::RepairTotals System::repair_totals() const {
  return impl_->pipe->dense ? impl_->pipe->dense->repair_totals() : dense::RepairTotals{};
}

void System::set_repair_callback(dense::DenseMapper::RepairCallback callback) {
  impl_->repair_callback = std::move(callback);
  if (impl_->pipe->dense) impl_->pipe->dense->set_repair_callback(impl_->repair_callback);
}

TrackingState System::state() const {
  std::lock_guard lock(impl_->pipe->map.mutex());
  return impl_->pipe->tracker.state();
}

TrackResult System::track_rgbd(const cv::Mat& rgb, const cv::Mat& depth, double timestamp, const cv::Mat& mask) {
  Impl& s = *impl_;
  if (s.shut_down) throw Error("track_rgbd: the system has been shut down");
  s.errors.rethrow();
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
  return s.track(rgb, depth, timestamp, mask);
}

TrackResult System::Impl::track(const cv::Mat& rgb, const cv::Mat& depth, double timestamp, const cv::Mat& mask) {
  Pipeline& p = *pipe;
  const camera::PinholeCamera& cam = config.camera;
  TrackResult result;
  const auto t0 = Clock::now();
  const std::uint64_t id = next_frame_id++;
  // The network starts on this frame now and runs while the features are found (Fig. 1).
  p.front_end.submit(id, timestamp, rgb);
  cv::Mat grey;
  if (rgb.channels() == 3) cv::cvtColor(rgb, grey, cam.rgb_order ? cv::COLOR_RGB2GRAY : cv::COLOR_BGR2GRAY);
  else grey = rgb;
  cv::Mat depth_m;
  if (depth.type() == CV_16UC1) depth.convertTo(depth_m, CV_32F, 1.0 / cam.depth_map_factor);
  else depth_m = depth;
  // The front end keeps the depth of recent frames: its own copy, not the caller's buffer.
  const bool keeps_depth = p.front_end.uses_segmentation() && depth.type() == CV_32FC1;
  cv::Mat dynamic_mask = mask;
  auto extraction = data::Frame::Extraction::Full;
  if (p.front_end.uses_segmentation()) p.extractor.detect(grey);
  const auto w0 = Clock::now();
  const dynamic::SemanticMask semantic =
      p.front_end.mask(id, keeps_depth ? depth_m.clone() : depth_m, p.tracker.predicted_pose());
  if (p.front_end.uses_segmentation()) {
    if (!semantic.mask.empty()) {
      if (dynamic_mask.empty()) {
        dynamic_mask = semantic.mask;
      } else {
        cv::Mat merged;  // a new buffer: dynamic_mask still shares the caller's
        cv::bitwise_or(mask, semantic.mask, merged);
        dynamic_mask = merged;
      }
    }
    result.timing.mask_wait = seconds(w0, Clock::now());
    extraction = data::Frame::Extraction::DescribeDetected;
  }
  result.dynamic.mask_frame = semantic.mask_frame;
  result.dynamic.mask_age = semantic.mask_age;
  result.timing.segmentation = semantic.segmentation_seconds;
  data::Frame frame(id, timestamp, grey, depth_m, dynamic_mask, p.extractor, p.undistorter, cam, extraction);
  const auto t1 = Clock::now();
  const tracking::TrackOutcome outcome = p.tracker.track(frame);
  const auto t2 = Clock::now();
  // A new keyframe goes to the dense stage with its images.
  if (p.dense && outcome.new_keyframe != nullptr) {
    cv::Mat bgr;
    if (rgb.channels() == 1) cv::cvtColor(rgb, bgr, cv::COLOR_GRAY2BGR);
    else if (cam.rgb_order) cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
    else bgr = rgb.clone();
    p.dense->add_keyframe(outcome.new_keyframe, std::move(bgr),
                          depth.type() == CV_32FC1 ? depth_m.clone() : depth_m,
                          frame.dynamic_mask.empty() ? cv::Mat() : frame.dynamic_mask.clone());
  }
  if (options.deterministic) p.process_queued();
  const auto t3 = Clock::now();

  result.state = outcome.state;
  result.timing.extraction = seconds(t0, t1) - result.timing.mask_wait;
  result.timing.waiting = outcome.wait_seconds;
  result.timing.geometry = outcome.geometry.seconds;
  result.timing.tracking = seconds(t1, t2) - outcome.wait_seconds - outcome.geometry.seconds;
  result.timing.mapping = seconds(t2, t3);
  result.inliers = outcome.inliers;
  result.dynamic.geometric_keypoints = outcome.geometry.keypoints_removed;
  result.dynamic.geometric_seeds = outcome.geometry.seeds;
  result.dynamic.keypoints = static_cast<int>(frame.size());
  result.dynamic.mask = frame.dynamic_mask;
  if (outcome.T_cw) result.T_wc = outcome.T_cw->inverse();
  p.front_end.frame_done(id, outcome.T_cw);
  if (publisher.has_subscribers()) publish_frame(result, outcome, frame, grey, rgb.channels() == 1);
  return result;
}

void System::Impl::publish_frame(const TrackResult& r, const tracking::TrackOutcome& outcome,
                                 const data::Frame& frame, const cv::Mat& grey, bool grey_shared) {
  if (outcome.new_keyframe != nullptr) {
    const map::KeyFrame* kf = outcome.new_keyframe;
    std::lock_guard lock(pipe->map.mutex());
    publisher.publish(
        events::KeyframeInserted{kf->id(), frame.id(), frame.timestamp(), kf->T_wc(),
                                                   static_cast<std::size_t>(kf->tracked_map_points(1))});
  }
  events::FrameTracked e;
  e.frame_id = frame.id();
  e.timestamp = frame.timestamp();
  e.state = r.state;
  e.T_wc = r.T_wc;
  e.timing = r.timing;
  e.inliers = r.inliers;
  e.mask_frame = r.dynamic.mask_frame;
  e.mask_age = r.dynamic.mask_age;
  e.geometric_keypoints = r.dynamic.geometric_keypoints;
  e.relocalized = outcome.relocalized;
  if (outcome.new_keyframe != nullptr) e.new_keyframe = outcome.new_keyframe->id();
  e.grey = grey_shared ? grey.clone() : grey;  // the caller may reuse its buffer
  e.mask = r.dynamic.mask.empty() ? cv::Mat() : r.dynamic.mask.clone();
  e.kept_keypoints = points_of(frame.keypoints());
  e.removed_keypoints = points_of(frame.removed_keypoints);
  publisher.publish(std::move(e));
}

io::Trajectory System::trajectory() const {
  std::lock_guard lock(impl_->pipe->map.mutex());
  io::Trajectory out;
  const tracking::FrameRecord* previous = nullptr;
  for (const tracking::FrameRecord& r : impl_->pipe->tracker.records()) {
    if (r.state != TrackingState::Ok || r.reference == nullptr) continue;
    out.push_back({r.timestamp, map::resolve_pose(r.reference, r.T_c_ref).inverse()});
    // Tripwire for a rare divergence seen once in a threaded static-mode run (one frame tens of
    // km off, its neighbours fine; not reproduced in 100 reruns): a camera does not move metres
    // between two consecutive frames (a relocalization after lost frames may, and is not checked).
    // Logged with what resolved the pose, for the report.
    if (previous != nullptr && r.frame_id == previous->frame_id + 1) {
      const double jump = (out.back().pose.translation() - out[out.size() - 2].pose.translation()).norm();
      if (jump > 5.0)
        spdlog::warn("trajectory: frame {} is {:.3g} m from frame {} ({:.3f} s before); reference keyframe {}{}, "
                     "{:.3g} m from it, {} inliers - a tracking or map error, please report it with this log",
                     r.frame_id, jump, previous->frame_id, r.timestamp - previous->timestamp, r.reference->id(),
                     r.reference->is_bad() ? " (culled)" : "", r.T_c_ref.translation().norm(), r.inliers);
    }
    previous = &r;
  }
  return out;
}

io::Trajectory System::keyframe_trajectory() const {
  std::lock_guard lock(impl_->pipe->map.mutex());
  io::Trajectory out;
  for (const map::KeyFrame* kf : impl_->pipe->map.keyframes()) out.push_back({kf->timestamp(), kf->T_wc()});
  return out;
}

void System::save_trajectory_tum(const std::filesystem::path& file) const { io::write_trajectory_tum(file, trajectory()); }

void System::save_keyframe_trajectory_tum(const std::filesystem::path& file) const {
  io::write_trajectory_tum(file, keyframe_trajectory());
}

MapStats System::map_stats() const {
  MapStats m;
  {
    std::lock_guard lock(impl_->pipe->map.mutex());
    m.keyframes = impl_->pipe->map.keyframe_count();
    m.map_points = impl_->pipe->map.map_point_count();
  }
  const auto ms = impl_->pipe->mapper.stats();
  m.culled_keyframes = ms.culled_keyframes;
  m.bundle_adjustments = ms.bundle_adjustments;
  if (impl_->pipe->loop_closer) {
    const auto ls = impl_->pipe->loop_closer->stats();
    m.loops = ls.loops.size();
    m.global_bundle_adjustments = ls.global_bundle_adjustments;
  }
  {
    std::lock_guard lock(impl_->pipe->map.mutex());
    m.relocalizations = impl_->pipe->tracker.relocalizations();
  }
  return m;
}

std::vector<loop::LoopEvent> System::loops() const {
  return impl_->pipe->loop_closer ? impl_->pipe->loop_closer->stats().loops : std::vector<loop::LoopEvent>{};
}

events::MapSnapshot System::map_snapshot() const {
  events::MapSnapshot out;
  std::lock_guard lock(impl_->pipe->map.mutex());
  for (const map::KeyFrame* kf : impl_->pipe->map.keyframes()) out.keyframes.push_back({kf->id(), kf->timestamp(), kf->T_wc()});
  for (const map::MapPoint* mp : impl_->pipe->map.map_points()) {
    if (mp->is_bad()) continue;
    events::MapPointSnapshot p{mp->id(), mp->position(), {}};
    for (const auto& [kf, index] : mp->observations()) p.keyframes.push_back(kf->id());
    out.points.push_back(std::move(p));
  }
  return out;
}

bool System::loop_closing_enabled() const { return impl_->pipe->loop_closer != nullptr; }

std::filesystem::path System::vocabulary_file() const { return impl_->vocabulary_file; }

}  // namespace lrd
