#pragma once
// Synthetic maps for the tests of the classes that own a thread or decide for one (local mapping,
// loop detection and closing, the global-BA merge): keyframes of a rendered textured plane
// (textured_plane.h) made the way tracking makes them — map points matched by projection
// (ground-truth data association) plus new points from depth — and the shipped vocabulary,
// loaded once per process.
//
// LoopScene is a camera that comes back: keyframes A0..A3 of the plane at their true poses,
// then B0..B3 seeing the same four views again with poses off by a rigid drift, as odometry
// would have them after a long way round. Each group is a covisible neighbourhood of its own
// (every keyframe matches the points of those before it, and makes new ones from depth); the
// groups share no map point. The four views are rendered once per process and copied.
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "lrd/features/descriptor_distance.h"
#include "lrd/map/keyframe_database.h"
#include "lrd/map/map.h"
#include "lrd/match/orb_matcher.h"
#include "lrd/place/vocabulary.h"
#include "lrd/util/project_files.h"
#include "textured_plane.h"

namespace lrd::test {

inline const place::Vocabulary& shipped_vocabulary() {
  static const place::Vocabulary vocabulary =
      place::Vocabulary::load(util::find_project_file("vocab/orb_vocab.lrdv"));
  return vocabulary;
}

// Tracking's data association, from geometry: each map point, projected with the frame's pose,
// goes to the free keypoint within `radius` pixels with the closest descriptor (at most
// OrbMatcher::kThLow bits away). Writes frame.map_points; returns the number of matches.
inline int associate(data::Frame& frame, const std::vector<map::MapPoint*>& points, float radius = 3.0f) {
  const camera::PinholeCamera& cam = frame.camera();
  std::vector<bool> used(frame.size(), false);
  for (std::size_t i = 0; i < frame.size(); ++i) used[i] = frame.map_points[i] != nullptr;
  int n = 0;
  for (map::MapPoint* mp : points) {
    if (mp == nullptr || mp->is_bad()) continue;
    const Eigen::Vector3d pc = frame.T_cw() * mp->position();
    if (pc.z() <= 0.0) continue;
    const Eigen::Vector2d uv = cam.project(pc);
    if (!frame.in_bounds(uv.x(), uv.y())) continue;
    int best = match::OrbMatcher::kThLow + 1;
    std::size_t best_j = SIZE_MAX;
    for (const std::size_t j :
         frame.features_in_area(static_cast<float>(uv.x()), static_cast<float>(uv.y()), radius)) {
      if (used[j]) continue;
      const int d =
          features::descriptor_distance(mp->descriptor().ptr(), frame.descriptors().ptr(static_cast<int>(j)));
      if (d < best) {
        best = d;
        best_j = j;
      }
    }
    if (best_j == SIZE_MAX) continue;
    used[best_j] = true;
    frame.map_points[best_j] = mp;
    ++n;
  }
  return n;
}

// A keyframe made the way tracking makes one (Tracker::create_new_keyframe): the frame's matches
// (frame.map_points) stay for local mapping to register, and every keypoint with depth and no
// match gets a new map point observed by the keyframe alone.
inline map::KeyFrame* tracking_keyframe(map::Map& map, const data::Frame& frame) {
  return keyframe_with_points(map, frame, /*unmatched_only=*/true);
}

// What local mapping does first with a new keyframe (LocalMapper::process_new_keyframe, without
// the place-recognition part): the matches become observations, the covisibility graph grows.
inline void register_keyframe(map::KeyFrame* kf) {
  for (std::size_t i = 0; i < kf->size(); ++i) {
    map::MapPoint* mp = kf->map_point(i);
    if (mp == nullptr || mp->is_bad() || mp->is_in_keyframe(kf)) continue;
    mp->add_observation(kf, i);
    mp->update_normal_and_depth();
    mp->compute_distinctive_descriptor();
  }
  kf->update_connections();
}

// Every good map point a keyframe holds.
inline std::vector<map::MapPoint*> points_of(const map::KeyFrame* kf) {
  std::vector<map::MapPoint*> out;
  for (map::MapPoint* mp : kf->map_points())
    if (mp != nullptr && !mp->is_bad()) out.push_back(mp);
  return out;
}

inline double translation_error(const Eigen::Isometry3d& T_cw, const Eigen::Isometry3d& T_true) {
  return (T_cw.inverse().translation() - T_true.inverse().translation()).norm();
}

class LoopScene {
 public:
  static constexpr int kViews = 4;

  // True poses of the four views: the camera orbits the plane's centre, 6 cm and 1.7 degrees
  // between views.
  static Eigen::Isometry3d true_pose(int k) { return pose(0.0, 0.03 * k, 0.0, -0.06 * k, 0.01 * k, 0.0); }
  // The odometry drift of the second visit: T_cw(estimated) = T_cw(true) * drift, so that its
  // map is the true one moved by drift^-1 (4 degrees and 33 cm).
  static Eigen::Isometry3d default_drift() { return pose(0.03, -0.05, 0.02, 0.25, -0.1, 0.15); }

  // The views of the plane, features extracted and bag of words computed, rendered once.
  static const std::vector<data::Frame>& views() {
    static const std::vector<data::Frame> frames = [] {
      TexturedPlane plane;
      std::vector<data::Frame> out;
      for (int k = 0; k < kViews; ++k) {
        out.push_back(plane.frame(static_cast<std::uint64_t>(k), true_pose(k)));
        out.back().compute_bow(shipped_vocabulary());
      }
      return out;
    }();
    return frames;
  }
  // A view of another plane (another texture): a place never seen before.
  static const data::Frame& elsewhere() {
    static const data::Frame frame = [] {
      TexturedPlane plane(11, 1.8, Eigen::Vector3d(-0.2, 0.1, -1.0));
      data::Frame f = plane.frame(100, Eigen::Isometry3d::Identity());
      f.compute_bow(shipped_vocabulary());
      return f;
    }();
    return frame;
  }

  // `database`: every keyframe is indexed in it (as local mapping does) unless null.
  explicit LoopScene(map::KeyFrameDatabase* database, const Eigen::Isometry3d& drift = default_drift())
      : drift_(drift), database_(database) {}

  // A keyframe of view `k` with the estimated pose `T_cw`, matching the points of `group` (and
  // adding its own new ones to it).
  map::KeyFrame* add(const data::Frame& view, const Eigen::Isometry3d& T_cw,
                     std::vector<map::MapPoint*>& group) {
    data::Frame f = view;
    f.set_pose(T_cw);
    (void)associate(f, group);
    map::KeyFrame* kf = tracking_keyframe(map, f);
    register_keyframe(kf);
    for (map::MapPoint* mp : points_of(kf))
      if (mp->reference_keyframe() == kf) group.push_back(mp);
    if (database_ != nullptr) database_->add(kf);
    return kf;
  }
  void add_first_visit() {
    for (int k = 0; k < kViews; ++k) first.push_back(add(views()[k], true_pose(k), first_points));
  }
  // Views [from, to) of the second visit.
  void add_second_visit(int from = 0, int to = kViews) {
    for (int k = from; k < to; ++k) back.push_back(add(views()[k], true_pose(k) * drift_, back_points));
  }
  // Two keyframes of the other place, covisible with each other only.
  std::vector<map::KeyFrame*> add_elsewhere() {
    std::vector<map::MapPoint*> pts;
    map::KeyFrame* a = add(elsewhere(), Eigen::Isometry3d::Identity(), pts);
    map::KeyFrame* b = add(elsewhere(), Eigen::Isometry3d::Identity(), pts);
    return {a, b};
  }

  [[nodiscard]] const Eigen::Isometry3d& drift() const { return drift_; }

  map::Map map;
  std::vector<map::KeyFrame*> first, back;
  std::vector<map::MapPoint*> first_points, back_points;

 private:
  Eigen::Isometry3d drift_;
  map::KeyFrameDatabase* database_;
};

}  // namespace lrd::test
