// BackgroundRepairer (paper §2.7, Fig. 12) on rendered frames with ground-truth poses and masks:
// the pixels hidden by people come back with the static scene's depth and colour; pixels no
// source saw stay invalid; sources' own dynamic pixels are never used. And the voxel grid / PLY
// pieces of the dense map.
#include <gtest/gtest.h>

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <string>
#include <tuple>
#include <vector>

#include "lrd/dense/background_repairer.h"
#include "lrd/dense/free_space_check.h"
#include "lrd/dense/ply_io.h"
#include "lrd/dense/voxel_grid.h"
#include "lrd/synth/synthetic_sequence.h"
#include "lrd/util/error.h"
#include "temp_dir.h"

namespace {

using lrd::dense::RgbdView;

RgbdView view_of(const lrd::synth::SynthFrame& f, double factor) {
  RgbdView v;
  v.bgr = f.rgb;
  f.depth.convertTo(v.depth, CV_32F, 1.0 / factor);
  v.dynamic = f.mask != 0;
  v.T_cw = f.pose.inverse();
  return v;
}

struct Walking {
  Walking()
      : seq([] {
          lrd::synth::SynthOptions o;
          o.preset = "walking_xyz";
          o.frames = 60;
          return o;
        }()) {}
  lrd::synth::SyntheticSequence seq;
};

const Walking& walking() {
  static const Walking w;
  return w;
}

}  // namespace

TEST(BackgroundRepairer, FillsThePeoplesPixelsWithTheStaticScene) {
  const auto& seq = walking().seq;
  const double factor = seq.camera().depth_map_factor;
  const lrd::synth::SynthFrame target = seq.render(55);
  std::vector<lrd::synth::SynthFrame> frames;
  for (int i = 0; i < 50; i += 5) frames.push_back(seq.render(i));
  std::vector<RgbdView> views;
  for (const auto& f : frames) views.push_back(view_of(f, factor));
  std::vector<const RgbdView*> sources;
  for (const RgbdView& v : views) sources.push_back(&v);

  const RgbdView t = view_of(target, factor);
  ASSERT_GT(cv::countNonZero(t.dynamic), 10000);
  lrd::dense::BackgroundRepairer repairer(seq.camera(), lrd::dense::RepairParams{});
  const auto r = repairer.repair(t, sources);
  EXPECT_EQ(r.dynamic_pixels, cv::countNonZero(t.dynamic));
  EXPECT_GT(r.fill_ratio(), 0.7);
  // Filled depths are the static scene's (no people copied in from the sources).
  cv::Mat truth;
  target.static_depth.convertTo(truth, CV_32F, 1.0 / factor);
  std::vector<float> err;
  int far_off = 0;
  for (int v = 0; v < truth.rows; ++v)
    for (int u = 0; u < truth.cols; ++u) {
      if (r.filled.at<unsigned char>(v, u) == 0 || truth.at<float>(v, u) <= 0) continue;
      const float e = std::abs(r.depth.at<float>(v, u) - truth.at<float>(v, u));
      err.push_back(e);
      far_off += e > 0.10f;
    }
  ASSERT_FALSE(err.empty());
  std::nth_element(err.begin(), err.begin() + static_cast<long>(err.size() / 2), err.end());
  EXPECT_LT(err[err.size() / 2], 0.02);
  EXPECT_LT(far_off, static_cast<int>(0.03 * static_cast<double>(err.size())));
  // Outside the dynamic region nothing changed; unfilled dynamic pixels are invalid.
  EXPECT_EQ(cv::countNonZero((r.depth != t.depth) & (t.dynamic == 0)), 0);
  EXPECT_EQ(cv::countNonZero((r.depth != 0) & (t.dynamic != 0) & (r.filled == 0)), 0);
}

TEST(BackgroundRepairer, NoSourcesOrNoMaskLeaveTheRegionInvalidOrTheImageAsIs) {
  const auto& seq = walking().seq;
  const RgbdView t = view_of(seq.render(30), seq.camera().depth_map_factor);
  lrd::dense::BackgroundRepairer repairer(seq.camera(), lrd::dense::RepairParams{});
  const auto none = repairer.repair(t, {});
  EXPECT_EQ(none.filled_pixels, 0);
  EXPECT_EQ(cv::countNonZero((none.depth != 0) & t.dynamic), 0);  // hidden pixels stay invalid
  RgbdView unmasked = t;
  unmasked.dynamic = cv::Mat();
  const auto same = repairer.repair(unmasked, {&t});
  EXPECT_EQ(same.dynamic_pixels, 0);
  EXPECT_EQ(cv::norm(same.depth, t.depth, cv::NORM_INF), 0.0);
}

TEST(VoxelGrid, OnePointPerVoxelAtTheMeanAndDeterministicOrder) {
  lrd::dense::VoxelGrid grid(0.01);
  grid.add({0.001f, 0.001f, 0.001f}, {10, 20, 30});
  grid.add({0.003f, 0.005f, 0.007f}, {30, 40, 50});
  grid.add({-0.004f, 0.0f, 0.0f}, {0, 0, 0});  // the voxel on the other side of 0
  const auto c = grid.cloud();
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c.points[0].x(), 0.002f, 1e-6);
  EXPECT_NEAR(c.points[0].z(), 0.004f, 1e-6);
  EXPECT_EQ(c.colours[0], cv::Vec3b(20, 30, 40));
  EXPECT_NEAR(c.points[1].x(), -0.004f, 1e-6);
}

TEST(PlyIo, BinaryRoundTripAndClearErrors) {
  lrd::test::TempDir tmp("ply");
  lrd::dense::PointCloud c;
  c.points = {{1.f, 2.f, 3.f}, {-0.5f, 0.25f, 8.f}};
  c.colours.emplace_back(1, 2, 3);
  c.colours.emplace_back(250, 128, 0);
  lrd::dense::write_ply(tmp.path() / "a.ply", c);
  const auto back = lrd::dense::read_ply(tmp.path() / "a.ply");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back.points[1], c.points[1]);
  EXPECT_EQ(back.colours[1], c.colours[1]);
  // ASCII with doubles and an extra property, as other tools write.
  const auto ascii =
      tmp.write("b.ply",
                "ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\nproperty double y\n"
                "property double z\nproperty float nx\nend_header\n0.5 1.5 2.5 1\n");
  const auto a = lrd::dense::read_ply(ascii);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_FLOAT_EQ(a.points[0].y(), 1.5f);
  EXPECT_TRUE(a.colours.empty());
  // Malformed headers: a clear error naming the file, never a huge allocation or an empty cloud.
  for (const auto& [name, text, words] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"neg.ply", "ply\nformat ascii 1.0\nelement vertex -1\nproperty float x\nend_header\n",
            "bad element"},
           {"huge.ply",
            "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty "
            "float y\n"
            "property float z\nend_header\n",
            "truncated"},
           {"novertex.ply", "ply\nformat ascii 1.0\nelement face 0\nend_header\n", "no vertex element"},
           {"big.ply", "ply\nformat binary_big_endian 1.0\nelement vertex 1\nend_header\n",
            "binary_big_endian"}}) {
    const auto file = tmp.write(name, text);
    try {
      (void)lrd::dense::read_ply(file);
      ADD_FAILURE() << name << " accepted";
    } catch (const lrd::Error& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  }
  const auto truncated =
      tmp.write("c.ply",
                "ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\n"
                "property float y\nproperty float z\nend_header\n");
  try {
    (void)lrd::dense::read_ply(truncated);
    FAIL() << "truncated file accepted";
  } catch (const lrd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("c.ply"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
}

TEST(FreeSpaceCheck, ViewsThatSeeThroughAPointVoteAgainstIt) {
  lrd::camera::PinholeCamera cam;  // tum3-like defaults, 640x480
  // A view of a wall 3 m ahead, the left half of its pixels dynamic.
  RgbdView view;
  view.depth = cv::Mat(cam.height, cam.width, CV_32F, cv::Scalar(3.0f));
  view.dynamic = cv::Mat::zeros(cam.height, cam.width, CV_8UC1);
  view.dynamic.colRange(0, cam.width / 2).setTo(255);
  view.T_cw = Eigen::Isometry3d::Identity();
  // The cloud's keyframe stands 0.2 m to the left of the view.
  Eigen::Isometry3d T_cw_cloud = Eigen::Isometry3d::Identity();
  T_cw_cloud.translation() = Eigen::Vector3d(0.2, 0.0, 0.0);  // world x = camera x - 0.2
  lrd::dense::PointCloud cloud;
  const auto in_cloud_frame = [&](const Eigen::Vector3d& world) -> Eigen::Vector3f {
    const Eigen::Vector3d c = T_cw_cloud * world;
    return c.cast<float>();
  };
  cloud.points = {in_cloud_frame({0.5, 0.0, 1.5}),  // floating in front of the wall, right half: seen through
                  in_cloud_frame({0.5, 0.0, 3.0}),  // on the wall
                  in_cloud_frame({-0.5, 0.0, 1.5}),   // in front, but where the view is dynamic: no judgement
                  in_cloud_frame({0.5, 0.0, 2.9}),    // within the margin of the wall
                  in_cloud_frame({0.5, 0.0, -1.0})};  // behind the view
  cloud.colours.assign(cloud.points.size(), cv::Vec3b(1, 2, 3));
  std::vector<std::uint8_t> votes(cloud.size(), 0);
  lrd::dense::vote_free_space(cloud, T_cw_cloud, view, cam, lrd::dense::FreeSpaceParams{}, votes);
  EXPECT_EQ(votes, (std::vector<std::uint8_t>{1, 0, 0, 0, 0}));
  lrd::dense::vote_free_space(cloud, T_cw_cloud, view, cam, lrd::dense::FreeSpaceParams{}, votes);
  EXPECT_EQ(votes[0], 2);  // one more view, one more vote
}
