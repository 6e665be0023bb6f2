// lrd::System's read side: trajectories, map statistics, snapshots and loops, each taken under
// the map mutex from the current Pipeline.
#include <spdlog/spdlog.h>

#include <mutex>

#include "lrd/map/keyframe.h"
#include "lrd/map/map_point.h"
#include "lrd/system_impl.h"

namespace lrd {

io::Trajectory System::trajectory() const {
  const map::Map& map = impl_->pipe->map;
  std::lock_guard lock(impl_->pipe->map.mutex());
  io::Trajectory out;
  const tracking::FrameRecord* previous = nullptr;
  for (const tracking::FrameRecord& r : impl_->pipe->tracker.records()) {
    if (r.state != TrackingState::Ok || !r.reference) continue;
    out.push_back({r.timestamp, map.resolve_pose(*r.reference, r.T_c_ref).inverse()});
    // Tripwire for a rare divergence seen once in a threaded static-mode run (one frame tens of
    // km off, its neighbours fine; not reproduced in 100 reruns): a camera does not move metres
    // between two consecutive frames (a relocalization after lost frames may, and is not checked).
    // Logged with what resolved the pose, for the report.
    if (previous != nullptr && r.frame_id == previous->frame_id + 1) {
      const double jump = (out.back().pose.translation() - out[out.size() - 2].pose.translation()).norm();
      if (jump > 5.0)
        spdlog::warn(
            "trajectory: frame {} is {:.3g} m from frame {} ({:.3f} s before); reference keyframe {}{}, "
            "{:.3g} m from it, {} inliers - a tracking or map error, please report it with this log",
            r.frame_id, jump, previous->frame_id, r.timestamp - previous->timestamp, *r.reference,
            map.keyframe(*r.reference) == nullptr ? " (culled)" : "", r.T_c_ref.translation().norm(),
            r.inliers);
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

void System::save_trajectory_tum(const std::filesystem::path& file) const {
  io::write_trajectory_tum(file, trajectory());
}

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
  m.implausible_local_bundle_adjustments = ms.implausible_bundle_adjustments;
  if (impl_->pipe->loop_closer) {
    const auto ls = impl_->pipe->loop_closer->stats();
    m.loops = ls.loops.size();
    m.global_bundle_adjustments = ls.global_bundle_adjustments;
    m.implausible_global_bundle_adjustments = ls.implausible_global_bundle_adjustments;
    m.rejected_loops = ls.rejected_loops;
  }
  {
    std::lock_guard lock(impl_->pipe->map.mutex());
    m.relocalizations = impl_->pipe->tracker.relocalizations();
    m.implausible_camera_motions = impl_->pipe->tracker.implausible_motions();
  }
  m.loaded_keyframes = impl_->loaded_keyframes;
  m.loaded_map_points = impl_->loaded_map_points;
  return m;
}

map::MapMemory System::map_memory() const {
  std::lock_guard lock(impl_->pipe->map.mutex());
  return impl_->pipe->map.memory();
}

std::vector<loop::LoopEvent> System::loops() const {
  return impl_->pipe->loop_closer ? impl_->pipe->loop_closer->stats().loops : std::vector<loop::LoopEvent>{};
}

std::vector<loop::GlobalBaRun> System::global_ba_runs() const {
  return impl_->pipe->loop_closer ? impl_->pipe->loop_closer->stats().global_ba_runs
                                  : std::vector<loop::GlobalBaRun>{};
}

events::MapSnapshot System::map_snapshot() const {
  events::MapSnapshot out;
  std::lock_guard lock(impl_->pipe->map.mutex());
  for (const map::KeyFrame* kf : impl_->pipe->map.keyframes())
    out.keyframes.push_back({kf->id(), kf->timestamp(), kf->T_wc()});
  for (const map::MapPoint* mp : impl_->pipe->map.map_points()) {
    if (mp->is_bad()) continue;
    events::MapPointSnapshot p{mp->id(), mp->position(), {}};
    for (const auto& [kf, index] : mp->observations()) p.keyframes.push_back(kf->id());
    out.points.push_back(std::move(p));
  }
  return out;
}

bool System::loop_closing_enabled() const {
  return impl_->pipe->loop_closer != nullptr;
}

std::filesystem::path System::vocabulary_file() const {
  return impl_->vocabulary_file;
}

}  // namespace lrd
