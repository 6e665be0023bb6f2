#include "lrd/system.h"

#include <fmt/format.h>

#include <chrono>
#include <deque>
#include <limits>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

#include "lrd/data/frame.h"
#include "lrd/dynamic/dynamic_point_filter.h"
#include "lrd/dynamic/mask_propagator.h"
#include "lrd/features/keypoint_undistorter.h"
#include "lrd/features/orb_extractor.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/map.h"
#include "lrd/loop/loop_closer.h"
#include "lrd/mapping/local_mapper.h"
#include "lrd/place/keyframe_database.h"
#include "lrd/place/vocabulary.h"
#include "lrd/segmentation/mask_folder_segmenter.h"
#include "lrd/segmentation/onnx_segmenter.h"
#include "lrd/segmentation/segmentation_worker.h"
#include "lrd/tracking/tracker.h"
#include "lrd/util/error.h"
#include "lrd/util/project_files.h"

namespace lrd {

namespace {
using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

std::string describe(const cv::Mat& m) {
  return fmt::format("{}x{} {}", m.cols, m.rows, cv::typeToString(m.type()));
}


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

std::unique_ptr<segmentation::Segmenter> make_segmenter(const segmentation::SegmentationParams& p) {
  switch (p.backend) {
    case segmentation::Backend::Onnx: return std::make_unique<segmentation::OnnxSegmenter>(p.onnx);
    case segmentation::Backend::Masks: return std::make_unique<segmentation::MaskFolderSegmenter>(p.masks);
    case segmentation::Backend::None: break;
  }
  return nullptr;
}

// A recent frame's depth and pose, to carry an older mask over to the current frame.
struct RecentFrame {
  std::uint64_t id = 0;
  cv::Mat depth;
  std::optional<Eigen::Isometry3d> T_cw;
};
constexpr std::size_t kRecentFrames = 30;
constexpr const char* kShippedVocabulary = "vocab/orb_vocab.lrdv";
}  // namespace

struct System::Impl {
  Impl(const config::Config& cfg, SystemOptions opts)
      : config(cfg),
        options(opts),
        dynamic_params(dynamic::DynamicParams::from_config(cfg.dynamic)),
        segmentation_params(opts.segmentation ? *opts.segmentation
                                              : segmentation::SegmentationParams::from_config(
                                                    cfg.segmentation, cfg.file.empty() ? std::filesystem::path{}
                                                                                       : cfg.file.parent_path())),
        extractor(cfg.features),
        undistorter(cfg.camera),
        loop_params(loop::LoopClosingParams::from_config(
            cfg.loop_closing, cfg.file.empty() ? std::filesystem::path{} : cfg.file.parent_path())),
        mapper(map, mapping::LocalMapperParams::from_config(cfg.mapping), !opts.deterministic),
        tracker(map, mapper, tracking::TrackerParams::from_config(cfg.tracking)),
        filter(dynamic_params.geometry) {
    if (opts.loop_closing) loop_params.enabled = *opts.loop_closing;
    if (opts.vocabulary) loop_params.vocabulary = *opts.vocabulary;
    // Place recognition: relocalization always, loop closing unless switched off. The shipped
    // vocabulary is optional (a library user may run without it); a configured one must load.
    vocabulary_file = loop_params.vocabulary.empty() ? util::find_project_file(kShippedVocabulary)
                                                     : loop_params.vocabulary;
    if (!loop_params.vocabulary.empty() || std::filesystem::exists(vocabulary_file)) {
      vocabulary = load_vocabulary(vocabulary_file);
      tracker.set_place_recognition(vocabulary.get(), &database);
      mapper.set_place_recognition(vocabulary.get(), &database);
      if (loop_params.enabled) {
        loop_closer = std::make_unique<loop::LoopCloser>(map, database, mapper, loop_params, !opts.deterministic);
        mapper.set_keyframe_callback([this](map::KeyFrame* kf) { loop_closer->insert_keyframe(kf); });
      }
    } else {
      spdlog::warn("no vocabulary at {}: no relocalization or loop closing", vocabulary_file.string());
      vocabulary_file.clear();
    }
    if (opts.mode) dynamic_params.mode = *opts.mode;
    if (opts.deterministic) segmentation_params.schedule = segmentation::Schedule::Sync;
    const dynamic::DynamicMode mode = dynamic_params.mode;
    if (dynamic::uses_segmentation(mode)) {
      if (segmentation_params.backend == segmentation::Backend::None)
        throw Error("mode '" + dynamic::to_string(mode) +
                    "' needs a segmentation backend (segmentation.backend: onnx or masks; or --segmenter)");
      worker = std::make_unique<segmentation::SegmentationWorker>(make_segmenter(segmentation_params),
                                                                  segmentation_params.schedule, cfg.camera.rgb_order);
    }
    dense::DenseParams dense_params = dense::DenseParams::from_config(cfg.dense);
    if (opts.dense) dense_params.enabled = *opts.dense;
    if (dense_params.enabled)
      dense = std::make_unique<dense::DenseMapper>(map, cfg.camera, dense_params, !opts.deterministic);
    if (dynamic::uses_geometry(mode)) {
      tracker.set_dynamic_check([this](data::Frame& f, const std::vector<map::KeyFrame*>& nearby) {
        const auto t0 = std::chrono::steady_clock::now();
        // In geometric mode nothing was filtered before the first estimate: judge from a pose
        // the moving objects cannot drag, and start the final optimization from it.
        if (dynamic_params.mode == dynamic::DynamicMode::Geometric) {
          int inl = 0;
          const auto T = filter.robust_pose(f, &inl);
          spdlog::debug("frame {}: robust pose {} ({} inliers)", f.id(), T ? "ok" : "failed", inl);
          if (T) f.set_pose(*T);
        }
        const dynamic::GeometryCheckResult r = filter.check(f, current_depth, nearby);
        if (r.flagged_keypoints > 0) f.remove_keypoints(r.dynamic);
        if (!r.mask.empty()) {
          if (f.dynamic_mask.empty()) f.dynamic_mask = r.mask;
          else {
            cv::Mat merged;  // a new buffer: the frame's mask may share the caller's
            cv::bitwise_or(f.dynamic_mask, r.mask, merged);
            f.dynamic_mask = merged;
          }
        }
        spdlog::debug("frame {}: geometry check: {} keyframes, {} judged, {} moving, {} skipped (parallax), {} "
                      "keypoints removed",
                      f.id(), r.keyframes, r.judged, r.seeds, r.parallax_skipped, r.flagged_keypoints);
        last_check = r;
        geometry_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      });
    }
  }

  // The dilated mask for frame `id` from the segmentation thread (sync: its own; async: the
  // newest within the wait bound, carried over from its frame). Empty when none is ready.
  cv::Mat semantic_mask(std::uint64_t id, DynamicInfo& info, double& segmentation_seconds) {
    const bool sync = segmentation_params.schedule == segmentation::Schedule::Sync;
    // A frame the network was not given (async stride) takes the newest mask without waiting.
    const bool submitted = sync || id % static_cast<std::uint64_t>(segmentation_params.stride) == 0;
    const auto result = worker->wait(
        id, sync ? std::nullopt : std::optional<double>(submitted ? segmentation_params.max_wait_ms / 1000.0 : 0.0));
    if (!result) return {};
    cv::Mat mask = result->mask.clone();  // dilated in place below; the worker keeps its copy
    const auto age = static_cast<int>(id - result->frame_id);
    info.mask_frame = static_cast<std::int64_t>(result->frame_id);
    info.mask_age = age;
    segmentation_seconds = result->seconds;
    int dilation = segmentation_params.dilation_px;
    if (age > 0) {
      const auto predicted = tracker.predicted_pose();
      const auto it = std::find_if(recent.begin(), recent.end(), [&](const RecentFrame& r) { return r.id == result->frame_id; });
      if (predicted && it != recent.end() && it->T_cw)
        mask = dynamic::propagate_mask(mask, it->depth, *predicted * it->T_cw->inverse(), config.camera);
      dilation += std::min(segmentation_params.max_age_dilation_px,
                           static_cast<int>(std::lround(age * segmentation_params.age_dilation_px)));
    }
    dynamic::dilate_mask(mask, dilation);
    return mask;
  }

  config::Config config;
  SystemOptions options;
  dynamic::DynamicParams dynamic_params;
  segmentation::SegmentationParams segmentation_params;
  features::OrbExtractor extractor;
  features::KeypointUndistorter undistorter;
  map::Map map;
  loop::LoopClosingParams loop_params;
  std::filesystem::path vocabulary_file;
  std::shared_ptr<const place::Vocabulary> vocabulary;
  place::KeyFrameDatabase database;
  mapping::LocalMapper mapper;
  tracking::Tracker tracker;
  dynamic::DynamicPointFilter filter;
  std::unique_ptr<segmentation::SegmentationWorker> worker;
  std::unique_ptr<loop::LoopCloser> loop_closer;  // after `mapper`: destroyed first
  std::unique_ptr<dense::DenseMapper> dense;  // before `map` is destroyed: it reads keyframe poses
  std::deque<RecentFrame> recent;
  cv::Mat current_depth;  // the frame being tracked, for the geometry check
  dynamic::GeometryCheckResult last_check;
  double geometry_seconds = 0.0;
  std::uint64_t next_frame_id = 0;
  double last_timestamp = -std::numeric_limits<double>::infinity();
  bool shut_down = false;
};

System::System(const config::Config& config, SystemOptions options)
    : impl_(std::make_unique<Impl>(config, options)) {}

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
  if (impl_->worker) impl_->worker->shutdown();
  impl_->mapper.shutdown();
  if (impl_->loop_closer) impl_->loop_closer->shutdown();
  if (impl_->dense) impl_->dense->shutdown();
}

const config::Config& System::config() const { return impl_->config; }

dynamic::DynamicMode System::mode() const { return impl_->dynamic_params.mode; }

std::string System::segmentation_description() const {
  if (!impl_->worker) return "none";
  return impl_->worker->segmenter().describe() + ", " + segmentation::to_string(impl_->worker->schedule());
}

bool System::dense_enabled() const { return impl_->dense != nullptr; }

dense::PointCloud System::dense_map() const { return impl_->dense ? impl_->dense->cloud() : dense::PointCloud{}; }

dense::RepairTotals System::repair_totals() const {
  return impl_->dense ? impl_->dense->repair_totals() : dense::RepairTotals{};
}

void System::set_repair_callback(dense::DenseMapper::RepairCallback callback) {
  if (impl_->dense) impl_->dense->set_repair_callback(std::move(callback));
}

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
  const std::uint64_t id = s.next_frame_id++;
  // The network starts on this frame now and runs while the features are found (Fig. 1).
  // A copy: the caller may reuse its buffer while the network still reads this one.
  if (s.worker && (s.segmentation_params.schedule == segmentation::Schedule::Sync ||
                   id % static_cast<std::uint64_t>(s.segmentation_params.stride) == 0))
    s.worker->submit(id, timestamp, rgb.clone());
  cv::Mat grey;
  if (rgb.channels() == 3) cv::cvtColor(rgb, grey, cam.rgb_order ? cv::COLOR_RGB2GRAY : cv::COLOR_BGR2GRAY);
  else grey = rgb;
  cv::Mat depth_m;
  if (depth.type() == CV_16UC1) depth.convertTo(depth_m, CV_32F, 1.0 / cam.depth_map_factor);
  else depth_m = depth;
  cv::Mat dynamic_mask = mask;
  auto extraction = data::Frame::Extraction::Full;
  if (s.worker) {
    s.extractor.detect(grey);
    const auto w0 = Clock::now();
    cv::Mat semantic = s.semantic_mask(id, result.dynamic, result.timing.segmentation);
    if (!semantic.empty()) {
      if (dynamic_mask.empty()) dynamic_mask = semantic;
      else {
        cv::Mat merged;  // a new buffer: dynamic_mask still shares the caller's
        cv::bitwise_or(mask, semantic, merged);
        dynamic_mask = merged;
      }
    }
    result.timing.mask_wait = seconds(w0, Clock::now());
    extraction = data::Frame::Extraction::DescribeDetected;
  }
  data::Frame frame(id, timestamp, grey, depth_m, dynamic_mask, s.extractor, s.undistorter, cam, extraction);
  const auto t1 = Clock::now();
  double wait = 0.0;
  s.current_depth = depth_m;
  s.last_check = {};
  s.geometry_seconds = 0.0;
  result.state = s.tracker.track(frame, &wait);
  const auto t2 = Clock::now();
  // A new keyframe (this frame became the reference) goes to the dense stage with its images.
  const tracking::FrameRecord& rec = s.tracker.records().back();
  if (s.dense && rec.reference != nullptr && rec.reference->frame_id() == id) {
    cv::Mat bgr;
    if (rgb.channels() == 1) cv::cvtColor(rgb, bgr, cv::COLOR_GRAY2BGR);
    else if (cam.rgb_order) cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
    else bgr = rgb.clone();
    s.dense->add_keyframe(rec.reference, std::move(bgr), depth.type() == CV_32FC1 ? depth_m.clone() : depth_m,
                          frame.dynamic_mask.empty() ? cv::Mat() : frame.dynamic_mask.clone());
  }
  if (s.options.deterministic) {
    s.mapper.process_queued();
    if (s.loop_closer) s.loop_closer->process_queued();
    if (s.dense) s.dense->process_queued();
  }
  const auto t3 = Clock::now();

  result.timing.extraction = seconds(t0, t1) - result.timing.mask_wait;
  result.timing.waiting = wait;
  result.timing.geometry = s.geometry_seconds;
  result.timing.tracking = seconds(t1, t2) - wait - s.geometry_seconds;
  result.timing.mapping = seconds(t2, t3);
  result.inliers = s.tracker.records().back().inliers;
  result.dynamic.geometric_keypoints = s.last_check.flagged_keypoints;
  result.dynamic.geometric_seeds = s.last_check.seeds;
  result.dynamic.keypoints = static_cast<int>(frame.size());
  result.dynamic.mask = frame.dynamic_mask;
  if (result.state == TrackingState::Ok) result.T_wc = frame.T_wc();
  if (s.worker) {
    // Our own copy: a CV_32F depth still shares the caller's buffer.
    s.recent.push_back({id, depth.type() == CV_32FC1 ? depth_m.clone() : depth_m, frame.has_pose() && result.state == TrackingState::Ok
                                         ? std::optional<Eigen::Isometry3d>(frame.T_cw())
                                         : std::nullopt});
    if (s.recent.size() > kRecentFrames) s.recent.pop_front();
  }
  return result;
}

io::Trajectory System::trajectory() const {
  std::lock_guard lock(impl_->map.mutex());
  io::Trajectory out;
  const tracking::FrameRecord* previous = nullptr;
  for (const tracking::FrameRecord& r : impl_->tracker.records()) {
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
  if (impl_->loop_closer) {
    const auto ls = impl_->loop_closer->stats();
    m.loops = ls.loops.size();
    m.global_bundle_adjustments = ls.global_bundle_adjustments;
  }
  {
    std::lock_guard lock(impl_->map.mutex());
    m.relocalizations = impl_->tracker.relocalizations();
  }
  return m;
}

std::vector<loop::LoopEvent> System::loops() const {
  return impl_->loop_closer ? impl_->loop_closer->stats().loops : std::vector<loop::LoopEvent>{};
}

bool System::loop_closing_enabled() const { return impl_->loop_closer != nullptr; }

std::filesystem::path System::vocabulary_file() const { return impl_->vocabulary_file; }

}  // namespace lrd
