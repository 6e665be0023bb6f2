// The loop closer's global bundle adjustment (loop_closer.h, step 4): after each corrected loop it
// refines the whole map in its own thread, aborted when the next loop comes, and is merged
// without stopping tracking (optim/global_bundle_adjuster.h). Lock-step runs solve it in place.
#include <spdlog/spdlog.h>

#include <chrono>

#include "lrd/loop/loop_closer.h"
#include "lrd/map/map.h"
#include "lrd/optim/global_bundle_adjuster.h"
#include "lrd/util/fault_injection.h"
#include "lrd/util/thread_priority.h"

namespace lrd::loop {

void LoopCloser::start_global_ba(std::uint64_t run) {
  stop_global_ba();
  if (!threaded_) {
    run_global_ba(run);
    return;
  }
  abort_global_ba_.store(false);
  global_ba_thread_ = std::thread([this, run] {
    util::name_this_thread("lrd-global-ba");
    try {
      run_global_ba(run);
    } catch (...) {
      errors_->capture("global BA");
    }
  });
}

void LoopCloser::stop_global_ba() {
  abort_global_ba_.store(true);
  if (global_ba_thread_.joinable()) global_ba_thread_.join();
  abort_global_ba_.store(false);
}

void LoopCloser::run_global_ba(std::uint64_t run) {
  // Keeps keyframe and map-point pointers while it solves without the map mutex.
  const map::ReclamationMembership member(map_.reclamation(), "global BA");
  util::check_fault_point("global_ba");
  const auto t0 = std::chrono::steady_clock::now();
  optim::GlobalBundleAdjustmentParams gp;
  gp.iterations = params_.global_ba_iterations;
  gp.max_edge_change_m = params_.global_ba_max_edge_change_m;
  gp.max_edge_change_deg = params_.global_ba_max_edge_change_deg;
  const auto s = optim::global_bundle_adjustment(map_, run, threaded_ ? &abort_global_ba_ : nullptr, gp);
  if (s.implausible)
    spdlog::warn(
        "global BA after loop at keyframe {} rejected: it would {}, its parent or tracked beside it (limits "
        "{} m, {} deg); the map keeps the pose-graph result",
        run, s.odometry_change.beyond(gp.max_edge_change_m, gp.max_edge_change_deg), gp.max_edge_change_m,
        gp.max_edge_change_deg);
  else
    spdlog::info(
        "global BA after loop at keyframe {}: {} keyframes, {} points, rms {:.2f} -> {:.2f} px, "
        "keyframes moved against their parents and linked keyframes by up to {:.3f} m{}",
        run, s.keyframes, s.points, s.initial_rms_px, s.final_rms_px, s.odometry_change.metres,
        s.aborted ? " (aborted)" : "");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::lock_guard lock(stats_mutex_);
  ++stats_.global_bundle_adjustments;
  if (s.aborted) ++stats_.aborted_global_bundle_adjustments;
  if (s.implausible) ++stats_.implausible_global_bundle_adjustments;
  stats_.global_ba_seconds += seconds;
  stats_.global_ba_runs.push_back({run, s.keyframes, s.points, seconds, s.aborted, s.implausible});
}

}  // namespace lrd::loop
