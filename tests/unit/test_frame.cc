// data::Frame on synthetic RGB-D frames: depth and virtual right coordinate per keypoint, grid
// search equal to brute force, masks respected, and keypoints that re-appear where the ground
// truth geometry says they must.
#include <gtest/gtest.h>

#include <opencv2/core/hal/hal.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "lrd/data/frame.h"
#include "lrd/synth/synthetic_sequence.h"

namespace {

struct Fixture {
  lrd::synth::SyntheticSequence seq;
  lrd::features::OrbExtractor extractor{lrd::features::OrbParams{}};
  lrd::features::KeypointUndistorter undistorter;
  explicit Fixture(const char* preset)
      : seq([&] {
          lrd::synth::SynthOptions o;
          o.preset = preset;
          o.frames = 40;
          return o;
        }()),
        undistorter(seq.camera()) {}

  lrd::data::Frame frame(int i, const cv::Mat& mask = {}) {
    const auto f = seq.render(i);
    cv::Mat grey, depth;
    cv::cvtColor(f.rgb, grey, cv::COLOR_BGR2GRAY);
    f.depth.convertTo(depth, CV_32F, 1.0 / seq.camera().depth_map_factor);
    lrd::data::Frame fr(static_cast<std::uint64_t>(i), f.timestamp, grey, depth, mask, extractor, undistorter,
                        seq.camera());
    fr.set_pose(f.pose.inverse());
    return fr;
  }
};

}  // namespace

TEST(Frame, DepthAndVirtualRightPerKeypoint) {
  Fixture fx("static_xyz");
  const auto f = fx.frame(10);
  const auto raw = fx.seq.render(10).depth;
  ASSERT_GT(f.size(), 800u);
  std::size_t with_depth = 0, close = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const cv::Point2f p = f.keypoints()[i].pt;
    const double d =
        raw.at<std::uint16_t>(static_cast<int>(std::lround(p.y)), static_cast<int>(std::lround(p.x))) /
        5000.0;
    if (d > 0) {
      ++with_depth;
      EXPECT_NEAR(f.depth(i), d, 1e-6);
      EXPECT_NEAR(f.u_right(i), f.undistorted()[i].pt.x - 40.0 / d, 1e-3);
      close += f.is_close(i);
      EXPECT_EQ(f.is_close(i), d < 40.0 * 40.0 / 535.4);
    } else {
      EXPECT_LT(f.depth(i), 0.0f);
      EXPECT_LT(f.u_right(i), 0.0f);
    }
  }
  EXPECT_GT(with_depth, 0.8 * f.size());
  EXPECT_GT(close, 0u);
}

TEST(Frame, GridSearchEqualsBruteForce) {
  Fixture fx("static_halfsphere");
  const auto f = fx.frame(5);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> ux(-20, 660), uy(-20, 500), ur(1, 60);
  for (int trial = 0; trial < 200; ++trial) {
    const float x = ux(rng), y = uy(rng), r = ur(rng);
    const int lo = trial % 3 == 0 ? 2 : -1, hi = trial % 4 == 0 ? 4 : -1;
    std::vector<std::size_t> expected;
    for (std::size_t i = 0; i < f.size(); ++i) {
      const auto& kp = f.undistorted()[i];
      if ((lo >= 0 && kp.octave < lo) || (hi >= 0 && kp.octave > hi)) continue;
      if (std::abs(kp.pt.x - x) <= r && std::abs(kp.pt.y - y) <= r) expected.push_back(i);
    }
    EXPECT_EQ(f.features_in_area(x, y, r, lo, hi), expected);
  }
}

TEST(Frame, MaskedPixelsGiveNoFeatures) {
  Fixture fx("static_xyz");
  cv::Mat mask = cv::Mat::zeros(480, 640, CV_8U);
  const cv::Rect region(200, 100, 240, 260);
  mask(region).setTo(255);
  const auto f = fx.frame(3, mask);
  EXPECT_GT(f.size(), 700u);
  EXPECT_EQ(static_cast<int>(f.size()), f.descriptors().rows);
  for (const auto& kp : f.keypoints())
    EXPECT_FALSE(region.contains(cv::Point(cvRound(kp.pt.x), cvRound(kp.pt.y))));
}

TEST(Frame, KeypointsReappearWhereGroundTruthGeometrySays) {
  Fixture fx("static_xyz");
  const auto a = fx.frame(10), b = fx.frame(16);
  int tested = 0, found = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto pw = a.unproject_world(i);
    if (!pw) continue;
    const Eigen::Vector3d pb = b.T_cw() * *pw;
    if (pb.z() <= 0.1) continue;
    const Eigen::Vector2d uv = fx.seq.camera().project(pb);
    const int level = a.undistorted()[i].octave;
    const auto near = b.features_in_area(static_cast<float>(uv.x()), static_cast<float>(uv.y()),
                                         3.0f * b.scale_factors()[level], std::max(0, level - 1), level + 1);
    if (near.empty() && (uv.x() < 20 || uv.y() < 20 || uv.x() > 620 || uv.y() > 460)) continue;
    ++tested;
    int best = 256;
    for (std::size_t j : near)
      best = std::min(best, cv::hal::normHamming(a.descriptors().ptr<uchar>(static_cast<int>(i)),
                                                 b.descriptors().ptr<uchar>(static_cast<int>(j)), 32));
    found += best <= 64;  // between ORB-SLAM2's TH_LOW (50) and TH_HIGH (100)
  }
  ASSERT_GT(tested, 500);
  // Repeatability of ORB between frames 0.2 s apart, with occlusions and sensor noise.
  EXPECT_GT(static_cast<double>(found) / tested, 0.5) << found << " of " << tested;
}
