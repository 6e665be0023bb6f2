#pragma once
// A map of keyframes for graph tests: copies of one real frame (features of a rendered textured
// plane) at chosen poses, with hand-made observations that set the covisibility weights.
#include <vector>

#include "lrd/map/map.h"
#include "textured_plane.h"

namespace lrd::test {

// One set of features; keypoints on the left half have no depth (monocular observations, weight
// 1), the others have it (weight 2).
struct KeyFrameGraph {
  lrd::test::TexturedPlane scene;
  lrd::map::Map map;
  lrd::data::Frame frame;
  std::vector<std::size_t> stereo, mono;  // keypoint indices by kind
  std::size_t next_stereo = 0, next_mono = 0;

  KeyFrameGraph() : frame(make_frame(scene)) {
    for (std::size_t i = 0; i < frame.size(); ++i) (frame.u_right(i) >= 0.0f ? stereo : mono).push_back(i);
  }
  static lrd::data::Frame make_frame(lrd::test::TexturedPlane& scene) {
    cv::Mat no_depth = cv::Mat::zeros(480, 640, CV_8U);
    no_depth.colRange(0, 320).setTo(255);
    return scene.frame(0, Eigen::Isometry3d::Identity(), no_depth);
  }

  lrd::map::KeyFrame* keyframe(const Eigen::Isometry3d& T_cw = Eigen::Isometry3d::Identity()) {
    lrd::data::Frame f = frame;
    f.set_pose(T_cw);
    return map.create_keyframe(f);
  }

  // A new map point seen by `kfs` through a fresh keypoint (the same index in each of them).
  lrd::map::MapPoint* point(const std::vector<lrd::map::KeyFrame*>& kfs, bool with_depth = true,
                            const Eigen::Vector3d& x = Eigen::Vector3d(0.0, 0.0, 2.0)) {
    const std::size_t idx = with_depth ? stereo.at(next_stereo++) : mono.at(next_mono++);
    lrd::map::MapPoint* mp = map.create_map_point(x, kfs.front(), 0);
    for (lrd::map::KeyFrame* kf : kfs) {
      mp->add_observation(kf, idx);
      kf->add_map_point(mp, idx);
    }
    return mp;
  }
  std::vector<lrd::map::MapPoint*> points(int n, const std::vector<lrd::map::KeyFrame*>& kfs) {
    std::vector<lrd::map::MapPoint*> out;
    for (int k = 0; k < n; ++k) out.push_back(point(kfs));
    return out;
  }
};

}  // namespace lrd::test
