#include "lrd/system.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "lrd/data/frame.h"
#include "lrd/data/rgbd_input.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/map_point.h"
#include "lrd/system_impl.h"
#include "lrd/util/error.h"
#include "lrd/util/project_files.h"
#include "lrd/util/yardstick.h"

namespace lrd {

namespace {
using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

constexpr const char* kShippedVocabulary = "vocab/orb_vocab.lrdv";

}  // namespace

System::Impl::Impl(const config::Config& cfg, SystemParams p, SystemOptions opts)
    : config(cfg), params(std::move(p)), options(opts), publisher(errors, opts.max_queued_frame_events) {
  // The shipped vocabulary is optional (a library user may run without it); a configured one
  // must load.
  const std::filesystem::path& configured = params.loop_closing.vocabulary;
  vocabulary_file = configured.empty() ? util::find_project_file(kShippedVocabulary) : configured;
  if (!configured.empty() || std::filesystem::exists(vocabulary_file)) {
    vocabulary = place::Vocabulary::load_shared(vocabulary_file);
  } else {
    spdlog::warn("no vocabulary at {}: no relocalization or loop closing", vocabulary_file.string());
    vocabulary_file.clear();
  }
  if (options.yardstick) yardstick_orb = cv::ORB::create(1000, 1.2f, 8);
  start_pipeline();
}

std::unique_ptr<Pipeline> System::Impl::make_pipeline(std::uint32_t generation) {
  auto fresh = std::make_unique<Pipeline>(config, params, options.deterministic, vocabulary.get(), errors,
                                          publisher, generation);
  if (repair_callback && fresh->dense) fresh->dense->set_repair_callback(repair_callback);
  fresh->tracker.set_localization_only(options.localization_only);
  return fresh;
}

void System::Impl::start_pipeline() {
  // Built whole before it replaces the old one: a failure leaves `pipe` as it was.
  pipe = make_pipeline(next_generation);
  ++next_generation;
  loaded_keyframes = loaded_map_points = 0;
}

System::System(const config::Config& config, SystemOptions options)
    : System(config, SystemParams::from_config(config, options), options) {}

System::System(const config::Config& config, SystemParams params, SystemOptions options)
    : impl_(std::make_unique<Impl>(config, std::move(params), options)) {}

System::~System() {
  try {
    shutdown();
  } catch (const std::exception& e) {
    // While another exception unwinds the caller, that one is the error to report.
    if (std::uncaught_exceptions() == 0) spdlog::error("shutdown: {}", e.what());
  } catch (...) {
  }
}

void System::shutdown() {
  if (impl_->shut_down) return;
  impl_->shut_down = true;
  if (!impl_->failure.empty()) {
    // track_rgbd already threw the error that stopped the system: stop the rest quietly (what
    // else fails now follows from it).
    try {
      impl_->pipe->shutdown();
    } catch (const std::exception& e) {
      spdlog::debug("shutdown after '{}': {}", impl_->failure, e.what());
    }
    impl_->publisher.shutdown();
    return;
  }
  std::exception_ptr stage_error;
  try {
    impl_->pipe->shutdown();
  } catch (...) {
    stage_error = std::current_exception();
  }
  impl_->publisher.shutdown();
  // A thread's first error is the one to report (a stage's shutdown error then follows from it).
  impl_->errors.rethrow();
  if (stage_error) std::rethrow_exception(stage_error);
}

void System::reset() {
  Impl& s = *impl_;
  if (s.shut_down) throw Error("reset: the system has been shut down");
  // The old map goes whatever state it is in; errors of its threads go with it (logged). A failed
  // publisher cannot be restarted: its subscribers would miss the new map.
  try {
    s.pipe->shutdown();
  } catch (const std::exception& e) {
    spdlog::warn("reset: the old map's threads stopped with: {}", e.what());
  }
  if (s.publisher.failed()) throw Error("reset: " + s.errors.message());
  if (s.errors.has_error()) spdlog::warn("reset: the old map stopped at: {}", s.errors.message());
  s.errors.clear();
  s.failure.clear();
  s.start_pipeline();
  s.last_timestamp = -std::numeric_limits<double>::infinity();
}

void System::subscribe(std::shared_ptr<events::Subscriber> subscriber) {
  impl_->publisher.subscribe(std::move(subscriber));
}

events::PublisherStats System::publisher_stats() const {
  return impl_->publisher.stats();
}

const config::Config& System::config() const {
  return impl_->config;
}

dynamic::DynamicMode System::mode() const {
  return impl_->params.dynamic.mode;
}

std::string System::segmentation_description() const {
  return impl_->pipe->front_end.segmentation_description();
}

bool System::dense_enabled() const {
  return impl_->pipe->dense != nullptr;
}

dense::PointCloud System::dense_map() const {
  return impl_->pipe->dense ? impl_->pipe->dense->cloud() : dense::PointCloud{};
}

bool System::occupancy_enabled() const {
  return impl_->pipe->dense != nullptr && impl_->params.occupancy.enabled;
}

const occupancy::OccupancyParams& System::occupancy_params() const {
  return impl_->params.occupancy;
}

occupancy::Occupancy System::occupancy() const {
  const auto clouds = impl_->pipe->dense ? impl_->pipe->dense->keyframe_clouds()
                                         : std::vector<dense::DenseMapper::KeyframeCloud>{};
  return occupancy::build_occupancy(clouds, impl_->params.occupancy);
}

dense::RepairTotals System::repair_totals() const {
  return impl_->pipe->dense ? impl_->pipe->dense->repair_totals() : dense::RepairTotals{};
}

dense::DenseStorage System::dense_storage() const {
  return impl_->pipe->dense ? impl_->pipe->dense->storage() : dense::DenseStorage{};
}

void System::set_repair_callback(dense::DenseMapper::RepairCallback callback) {
  impl_->repair_callback = std::move(callback);
  if (impl_->pipe->dense) impl_->pipe->dense->set_repair_callback(impl_->repair_callback);
}

TrackingState System::state() const {
  std::lock_guard lock(impl_->pipe->map.mutex());
  return impl_->pipe->tracker.state();
}

TrackResult System::track_rgbd(const cv::Mat& rgb, const cv::Mat& depth, double timestamp,
                               const cv::Mat& mask) {
  Impl& s = *impl_;
  if (s.shut_down) throw Error("track_rgbd: the system has been shut down");
  if (!s.failure.empty()) throw Error(s.failure);
  if (s.options.localization_only && s.loaded_keyframes == 0)
    throw Error("track_rgbd: localization only needs a map to localize in: load one first (load_map)");
  s.publisher.seal();  // subscribers are registered before the first frame
  if (s.errors.has_error()) {
    s.failure = s.errors.message();
    throw Error(s.failure);
  }
  data::check_rgbd_input(rgb, depth, mask, s.config.camera);
  if (!(timestamp > s.last_timestamp))
    throw Error(fmt::format("track_rgbd: timestamp {:.6f} does not increase (previous {:.6f})", timestamp,
                            s.last_timestamp));
  s.last_timestamp = timestamp;
  try {
    return s.track(rgb, depth, timestamp, mask);
  } catch (const std::exception& e) {
    // A stage failed in this thread (segmentation's result, a lock-step stage): the system stops.
    s.failure = e.what();
    throw;
  }
}

TrackResult System::Impl::track(const cv::Mat& rgb, const cv::Mat& depth, double timestamp,
                                const cv::Mat& mask) {
  Pipeline& p = *pipe;
  const camera::PinholeCamera& cam = config.camera;
  TrackResult result;
  const auto t0 = Clock::now();
  const std::uint64_t id = next_frame_id++;
  // The network starts on this frame now and runs while the features are found (Fig. 1).
  p.front_end.submit(id, timestamp, rgb);
  const cv::Mat grey = data::grey_of(rgb, cam);
  const cv::Mat depth_m = data::depth_in_metres(depth, cam);
  // The front end keeps the depth of the recent frames the network sees: its own copy, not the
  // caller's buffer (1.2 MB at 640x480, copied only where it is kept).
  const bool keeps_depth = p.front_end.keeps_depth_of(id) && depth.type() == CV_32FC1;
  cv::Mat dynamic_mask = mask;
  auto extraction = data::Frame::Extraction::Full;
  if (p.front_end.uses_segmentation()) p.extractor.detect(grey);
  const auto w0 = Clock::now();
  const dynamic::SemanticMask semantic = p.front_end.mask(id, depth_m, p.tracker.predicted_pose(timestamp));
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
  if (yardstick_orb) result.timing.yardstick = util::yardstick_seconds(*yardstick_orb, grey);
  const auto t1 = Clock::now();
  const tracking::TrackOutcome outcome = p.tracker.track(frame);
  const auto t2 = Clock::now();
  // The keyframe's event before those its processing causes (map changed, loop closed).
  if (outcome.new_keyframe != nullptr && publisher.has_subscribers())
    publisher.publish(events::KeyframeInserted{p.generation, outcome.new_keyframe_id, id, timestamp,
                                               outcome.new_keyframe_T_wc, outcome.new_keyframe_points});
  // A new keyframe goes to the dense stage with its images.
  if (p.dense && outcome.new_keyframe != nullptr) {
    p.dense->add_keyframe(outcome.new_keyframe, data::bgr_copy_of(rgb, cam),
                          depth.type() == CV_32FC1 ? depth_m.clone() : depth_m,
                          frame.dynamic_mask.empty() ? cv::Mat() : frame.dynamic_mask.clone(),
                          /*mask_carried=*/p.front_end.uses_segmentation() && semantic.mask_age != 0);
  }
  if (options.deterministic) p.process_queued();
  const auto t3 = Clock::now();

  result.state = outcome.state;
  result.timing.extraction = seconds(t0, t1) - result.timing.mask_wait - result.timing.yardstick;
  result.timing.waiting = outcome.wait_seconds;
  result.timing.geometry = outcome.geometry.seconds;
  result.timing.tracking = seconds(t1, t2) - outcome.wait_seconds - outcome.geometry.seconds;
  result.timing.mapping = seconds(t2, t3);
  result.inliers = outcome.inliers;
  result.local_keyframes = outcome.local_keyframes;
  result.local_points = outcome.local_points;
  result.dynamic.geometric_keypoints = outcome.geometry.keypoints_removed;
  result.dynamic.geometric_seeds = outcome.geometry.seeds;
  result.dynamic.keypoints = static_cast<int>(frame.size());
  result.dynamic.mask = frame.dynamic_mask;
  if (outcome.T_cw) result.T_wc = outcome.T_cw->inverse();
  p.front_end.frame_done(id, outcome.T_cw, keeps_depth ? depth_m.clone() : cv::Mat());
  if (publisher.has_subscribers()) publish_frame(result, outcome, frame, grey, rgb.channels() == 1);
  return result;
}

}  // namespace lrd
