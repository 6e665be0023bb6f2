// The harder dynamic content (docs/synthetic-benchmark.md): a seated person who stands up after
// several seconds and walks out of the view (sitting_standup), and a person walking at the camera
// until they fill most of the view beside one cut by the image border (walking_close).
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/synth/presets.h"
#include "lrd/synth/synthetic_sequence.h"

namespace {

struct Seen {
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  double in_view = 0.0;  // share of the actor's vertices in front of the camera and inside the image
};

// Where actor `index` of the scene is at time t, and how much of it the camera sees.
Seen seen(const lrd::synth::SceneScript& script, std::size_t index, double t) {
  lrd::synth::TriangleSoup soup;
  script.actors[index]->add_geometry(t, soup);
  const auto camera = lrd::camera::camera_preset("tum3");
  const Eigen::Isometry3d world_to_camera = script.camera->pose_at(t).inverse();
  Seen s;
  int n = 0, inside = 0;
  for (const auto& tri : soup.triangles())
    for (const auto& p : tri.p) {
      s.centroid += p;
      ++n;
      const Eigen::Vector3d c = world_to_camera * p.cast<double>();
      if (c.z() <= 0.1) continue;
      const Eigen::Vector2d uv = camera.project(c);
      inside += uv.x() >= 0 && uv.x() < camera.width && uv.y() >= 0 && uv.y() < camera.height;
    }
  s.centroid /= static_cast<float>(n);
  s.in_view = static_cast<double>(inside) / n;
  return s;
}

}  // namespace

TEST(HardPresets, TheStandingUpPersonSitsStillThenWalksOutOfTheView) {
  const auto textures = lrd::synth::SyntheticSequence::load_textures();
  const auto& spec = lrd::synth::find_preset("sitting_standup");
  const auto script = lrd::synth::build_scene_script(spec, *textures, 1, 30.0);
  ASSERT_EQ(script.actors.size(), 2u);
  // Seated for the first 8 s: shifting by centimetres, fully in view.
  const Seen early = seen(script, 0, 1.0), later = seen(script, 0, 7.5);
  EXPECT_LT((early.centroid - later.centroid).norm(), 0.1f);
  EXPECT_GT(early.in_view, 0.95);
  EXPECT_GT(later.in_view, 0.95);
  // Standing (the body's centre rises) and walking in view by 12 s...
  const Seen walking = seen(script, 0, 12.0);
  EXPECT_GT(walking.centroid.z() - later.centroid.z(), 0.15f);
  EXPECT_GT((walking.centroid - later.centroid).head<2>().norm(), 0.5f);
  // ...then out of the view for the rest of the sequence, standing still.
  for (double t : {20.0, 25.0, 29.9}) EXPECT_EQ(seen(script, 0, t).in_view, 0.0) << t;
  EXPECT_LT((seen(script, 0, 22.0).centroid - seen(script, 0, 29.0).centroid).norm(), 0.05f);
  // The other person sits on.
  EXPECT_LT((seen(script, 1, 1.0).centroid - seen(script, 1, 29.0).centroid).norm(), 0.1f);
  EXPECT_GT(seen(script, 1, 29.0).in_view, 0.95);
  // Left out of FNet-lite's training draw, as every preset added after it.
  EXPECT_TRUE(spec.held_out);
}

TEST(HardPresets, APersonWalksAtTheCameraAndFillsMostOfTheViewForOverASecond) {
  const auto textures = lrd::synth::SyntheticSequence::load_textures();
  const auto& spec = lrd::synth::find_preset("walking_close");
  const auto script = lrd::synth::build_scene_script(spec, *textures, 1, 30.0);
  ASSERT_EQ(script.actors.size(), 2u);
  // Their distance to the camera over the first 12 s: it comes down to under 0.6 m and stays there
  // for over a second.
  double closest = 1e9, near_from = -1.0, near_to = -1.0;
  for (int k = 0; k < 120; ++k) {
    const double t = 0.1 * k;
    const Eigen::Vector3f camera = script.camera->pose_at(t).translation().cast<float>();
    const float distance = (seen(script, 0, t).centroid - camera).head<2>().norm();
    closest = std::min<double>(closest, distance);
    if (distance < 0.6f && near_from < 0.0) near_from = t;
    if (distance < 0.6f && near_to < near_from + 2.0) near_to = t;
  }
  EXPECT_LT(closest, 0.6);
  ASSERT_GE(near_from, 0.0);
  EXPECT_GT(near_to - near_from, 1.0);
  // Inside that second they cover more than 70 % of the image (ground-truth mask).
  lrd::synth::SynthOptions o;
  o.preset = "walking_close";
  const lrd::synth::SyntheticSequence seq(o, textures);
  for (double t : {near_from + 0.3, near_to - 0.3}) {
    const auto frame = seq.render(static_cast<int>(std::lround(t * 30.0)));
    EXPECT_GT(cv::countNonZero(frame.mask), 0.7 * static_cast<double>(frame.mask.total())) << t;
  }
  // The box carrier is cut by the image border: in part in view at some moments.
  int cut = 0;
  for (int k = 0; k < 60; ++k) {
    const double share = seen(script, 1, 0.5 * k).in_view;
    cut += share > 0.05 && share < 0.9;
  }
  EXPECT_GT(cut, 10);
  EXPECT_TRUE(spec.held_out);
}
