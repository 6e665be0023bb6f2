// The ORB extractor: count, spread, masks, rotation invariance of orientation and descriptors,
// determinism; the quadtree distributor; keypoint undistortion.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/features/gaussian_smoother.h"
#include "lrd/features/keypoint_undistorter.h"
#include "lrd/features/orb_extractor.h"
#include "lrd/features/quadtree_distributor.h"
#include "lrd/synth/synthetic_sequence.h"
#include "lrd/util/error.h"

using lrd::features::KeypointUndistorter;
using lrd::features::OrbExtractor;
using lrd::features::OrbParams;

namespace {

// Grey frames of the textured synthetic room (rendered once for the whole suite).
const cv::Mat& textured_frame(int which = 0) {
  static const std::vector<cv::Mat> frames = [] {
    lrd::synth::SynthOptions o;
    o.preset = "static_xyz";
    o.frames = 40;
    const lrd::synth::SyntheticSequence seq(o);
    std::vector<cv::Mat> out;
    for (int i : {15, 35}) {  // not among the frames brief_pattern was learned on
      cv::Mat grey;
      cv::cvtColor(seq.render(i).rgb, grey, cv::COLOR_BGR2GRAY);
      out.push_back(grey);
    }
    return out;
  }();
  return frames.at(which);
}

struct Features {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
};

Features extract(const cv::Mat& grey, const cv::Mat& mask = cv::Mat()) {
  OrbExtractor orb{OrbParams{}};
  Features f;
  orb.extract(grey, mask, f.keypoints, f.descriptors);
  return f;
}

int hamming(const cv::Mat& a, int i, const cv::Mat& b, int j) {
  int d = 0;
  for (int k = 0; k < 32; ++k)
    d += std::popcount(static_cast<unsigned>(a.at<std::uint8_t>(i, k) ^ b.at<std::uint8_t>(j, k)));
  return d;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// Signed difference a - b of two angles in degrees, in (-180, 180].
double angle_diff(double a, double b) {
  double d = std::fmod(a - b, 360.0);
  if (d <= -180.0) d += 360.0;
  if (d > 180.0) d -= 360.0;
  return d;
}

// Pairs (i in `a`, j in `b`) of keypoints of the same octave where b's position is a's mapped by
// the 2x3 affine `m`, within `tol` level pixels; both away from b's image border.
std::vector<std::pair<int, int>> corresponding(const Features& a, const Features& b, const cv::Mat& m,
                                               cv::Size b_size, double tol) {
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < static_cast<int>(a.keypoints.size()); ++i) {
    const cv::KeyPoint& ka = a.keypoints[i];
    const double x = m.at<double>(0, 0) * ka.pt.x + m.at<double>(0, 1) * ka.pt.y + m.at<double>(0, 2);
    const double y = m.at<double>(1, 0) * ka.pt.x + m.at<double>(1, 1) * ka.pt.y + m.at<double>(1, 2);
    if (x < 60 || y < 60 || x > b_size.width - 60 || y > b_size.height - 60) continue;
    const double scale = std::pow(1.2, ka.octave);
    int best = -1;
    double best_d = tol * scale;
    for (int j = 0; j < static_cast<int>(b.keypoints.size()); ++j) {
      const cv::KeyPoint& kb = b.keypoints[j];
      if (kb.octave != ka.octave) continue;
      const double d = std::hypot(kb.pt.x - x, kb.pt.y - y);
      if (d < best_d) best_d = d, best = j;
    }
    if (best >= 0) pairs.emplace_back(i, best);
  }
  return pairs;
}

}  // namespace

TEST(OrbExtractor, CountsAndAttributes) {
  const cv::Mat& grey = textured_frame();
  OrbExtractor orb{OrbParams{}};
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  orb.extract(grey, cv::Mat(), kps, desc);
  EXPECT_GE(kps.size(), 900u);
  EXPECT_LE(kps.size(), 1000u);
  ASSERT_EQ(desc.rows, static_cast<int>(kps.size()));
  EXPECT_EQ(desc.cols, 32);
  EXPECT_EQ(desc.type(), CV_8U);

  ASSERT_EQ(orb.scale_factors().size(), 8u);
  EXPECT_FLOAT_EQ(orb.scale_factors()[0], 1.0f);
  EXPECT_NEAR(orb.scale_factors()[7], std::pow(1.2, 7), 1e-4);
  EXPECT_NEAR(orb.inv_scale_factors()[3], 1.0 / std::pow(1.2, 3), 1e-6);
  EXPECT_NEAR(orb.level_sigma2()[2], 1.2 * 1.2 * 1.2 * 1.2, 1e-5);
  EXPECT_NEAR(orb.inv_level_sigma2()[2] * orb.level_sigma2()[2], 1.0, 1e-6);
  int asked = 0;
  for (int n : orb.features_per_level()) asked += n;
  EXPECT_EQ(asked, 1000);
  EXPECT_GT(orb.features_per_level()[0], orb.features_per_level()[7]);

  std::vector<int> per_level(8, 0);
  int previous_octave = 0;
  for (const cv::KeyPoint& kp : kps) {
    ASSERT_GE(kp.octave, 0);
    ASSERT_LT(kp.octave, 8);
    EXPECT_GE(kp.octave, previous_octave) << "keypoints come in level order";
    previous_octave = kp.octave;
    ++per_level[kp.octave];
    EXPECT_GE(kp.angle, 0.0f);
    EXPECT_LT(kp.angle, 360.0f);
    EXPECT_GE(kp.response, 7.0f);
    EXPECT_NEAR(kp.size, 31.0 * orb.scale_factors()[kp.octave], 1e-3);
    EXPECT_GE(kp.pt.x, 15.0f);
    EXPECT_GE(kp.pt.y, 15.0f);
    EXPECT_LE(kp.pt.x, grey.cols - 16.0f);
    EXPECT_LE(kp.pt.y, grey.rows - 16.0f);
  }
  for (int l = 0; l < 8; ++l) EXPECT_GT(per_level[l], 0) << "level " << l;
  EXPECT_GT(per_level[0], per_level[7]);
}

TEST(OrbExtractor, SpreadsKeypointsOverTheImage) {
  const cv::Mat& grey = textured_frame();
  const Features f = extract(grey);
  // Texture per cell of a 4x4 grid: FAST corners at the low threshold.
  std::vector<cv::KeyPoint> corners;
  cv::FAST(grey, corners, 7, true);
  constexpr int kGrid = 4;
  auto cell = [&](const cv::Point2f& p) {
    const int cx = std::clamp(static_cast<int>(p.x * kGrid / grey.cols), 0, kGrid - 1);
    const int cy = std::clamp(static_cast<int>(p.y * kGrid / grey.rows), 0, kGrid - 1);
    return cy * kGrid + cx;
  };
  std::vector<int> texture(kGrid * kGrid, 0), ours(kGrid * kGrid, 0);
  for (const cv::KeyPoint& c : corners) ++texture[cell(c.pt)];
  for (const cv::KeyPoint& k : f.keypoints) ++ours[cell(k.pt)];
  int textured_cells = 0;
  for (int c = 0; c < kGrid * kGrid; ++c) {
    SCOPED_TRACE("cell " + std::to_string(c) + ": " + std::to_string(texture[c]) + " corners, " +
                 std::to_string(ours[c]) + " keypoints");
    if (texture[c] >= 50) {
      ++textured_cells;
      EXPECT_GE(ours[c], 10);
    }
    EXPECT_LE(ours[c], 0.15 * static_cast<double>(f.keypoints.size()));  // even share: 6.25 %
  }
  EXPECT_GE(textured_cells, 12);
  RecordProperty("max_cell_share_permille",
                 static_cast<int>(1000.0 * *std::max_element(ours.begin(), ours.end()) / f.keypoints.size()));
}

TEST(OrbExtractor, MaskedPixelsGetNoKeypoint) {
  const cv::Mat& grey = textured_frame();
  const cv::Rect region(200, 120, 240, 200);
  cv::Mat mask = cv::Mat::zeros(grey.size(), CV_8U);
  mask(region).setTo(1);
  const Features free = extract(grey);
  const Features masked = extract(grey, mask);
  ASSERT_EQ(masked.descriptors.rows, static_cast<int>(masked.keypoints.size()));
  auto inside = [&](const cv::KeyPoint& k) {
    return mask.at<std::uint8_t>(cvRound(k.pt.y), cvRound(k.pt.x)) != 0;
  };
  const auto in_free = std::count_if(free.keypoints.begin(), free.keypoints.end(), inside);
  const auto in_masked = std::count_if(masked.keypoints.begin(), masked.keypoints.end(), inside);
  EXPECT_GT(in_free, 100);
  EXPECT_EQ(in_masked, 0);
  const auto out_free = static_cast<long>(free.keypoints.size()) - in_free;
  const auto out_masked = static_cast<long>(masked.keypoints.size()) - in_masked;
  EXPECT_GE(out_masked, out_free);
  EXPECT_GE(masked.keypoints.size(), 900u) << "the budget moves to the unmasked image";

  // Keypoints outside the mask keep their descriptors where they are also found without it.
  int same = 0, compared = 0;
  for (std::size_t i = 0; i < masked.keypoints.size(); ++i) {
    for (std::size_t j = 0; j < free.keypoints.size(); ++j) {
      if (masked.keypoints[i].pt == free.keypoints[j].pt &&
          masked.keypoints[i].octave == free.keypoints[j].octave) {
        ++compared;
        same += std::memcmp(masked.descriptors.ptr(static_cast<int>(i)),
                            free.descriptors.ptr(static_cast<int>(j)), 32) == 0;
      }
    }
  }
  EXPECT_GT(compared, 300);
  EXPECT_EQ(same, compared);

  const Features none = extract(grey, cv::Mat(grey.size(), CV_8U, cv::Scalar(255)));
  EXPECT_TRUE(none.keypoints.empty());
  EXPECT_EQ(none.descriptors.rows, 0);
}

TEST(OrbExtractor, RejectsBadInput) {
  OrbExtractor orb{OrbParams{}};
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  const cv::Mat& grey = textured_frame();
  EXPECT_THROW(orb.extract(cv::Mat(), cv::Mat(), kps, desc), lrd::Error);
  EXPECT_THROW(orb.extract(cv::Mat(480, 640, CV_8UC3, cv::Scalar::all(0)), cv::Mat(), kps, desc), lrd::Error);
  EXPECT_THROW(orb.extract(grey, cv::Mat::zeros(240, 320, CV_8U), kps, desc), lrd::Error);
  OrbParams bad;
  bad.scale_factor = 0.8f;
  EXPECT_THROW(OrbExtractor{bad}, lrd::Error);
  bad = OrbParams{};
  bad.min_th_fast = 30;
  EXPECT_THROW(OrbExtractor{bad}, lrd::Error);
  // Tiny and flat images give nothing, without failing.
  orb.extract(cv::Mat(20, 20, CV_8U, cv::Scalar(9)), cv::Mat(), kps, desc);
  EXPECT_TRUE(kps.empty());
  orb.extract(cv::Mat(480, 640, CV_8U, cv::Scalar(128)), cv::Mat(), kps, desc);
  EXPECT_TRUE(kps.empty());
  EXPECT_EQ(desc.rows, 0);
}

TEST(OrbExtractor, DescriptorsAndAnglesFollowRotation) {
  // A square crop, so a 90 degree turn about its centre maps the image onto itself.
  const cv::Mat grey = textured_frame()(cv::Rect(80, 0, 480, 480)).clone();
  const cv::Point2f centre(0.5f * (grey.cols - 1), 0.5f * (grey.rows - 1));
  const Features base = extract(grey);
  for (const double degrees : {30.0, 90.0}) {
    SCOPED_TRACE(std::to_string(degrees) + " degrees");
    const cv::Mat m = cv::getRotationMatrix2D(centre, degrees, 1.0);  // counter-clockwise on screen
    cv::Mat turned;
    cv::warpAffine(grey, turned, m, grey.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
    const Features rot = extract(turned);
    const auto pairs = corresponding(base, rot, m, turned.size(), 1.0);
    ASSERT_GT(pairs.size(), 150u);
    std::vector<double> hamming_d, angle_err, random_d;
    for (const auto& [i, j] : pairs) {
      hamming_d.push_back(hamming(base.descriptors, i, rot.descriptors, j));
      // On screen the content turns counter-clockwise, which in image axes (y down) is -degrees.
      angle_err.push_back(std::abs(angle_diff(rot.keypoints[j].angle, base.keypoints[i].angle - degrees)));
    }
    std::mt19937 rng(7);
    for (int k = 0; k < 500; ++k) {
      const int i = static_cast<int>(rng() % base.keypoints.size());
      const int j = static_cast<int>(rng() % rot.keypoints.size());
      random_d.push_back(hamming(base.descriptors, i, rot.descriptors, j));
    }
    const std::string tag = std::to_string(static_cast<int>(degrees)) + "deg_";
    RecordProperty(tag + "pairs", static_cast<int>(pairs.size()));
    RecordProperty(tag + "median_hamming", static_cast<int>(median(hamming_d)));
    RecordProperty(tag + "median_random_hamming", static_cast<int>(median(random_d)));
    RecordProperty(tag + "median_angle_error_centideg", static_cast<int>(100.0 * median(angle_err)));
    EXPECT_LT(median(hamming_d), degrees == 90.0 ? 10.0 : 40.0);
    EXPECT_GT(median(random_d), 100.0);  // unrelated patches: near half the bits differ
    EXPECT_LT(median(random_d), 150.0);
    EXPECT_LT(median(angle_err), degrees == 90.0 ? 1.0 : 5.0);
  }
}

TEST(OrbExtractor, DeterministicBits) {
  const cv::Mat& grey = textured_frame(1);
  cv::Mat mask = cv::Mat::zeros(grey.size(), CV_8U);
  cv::circle(mask, {300, 260}, 90, cv::Scalar(1), cv::FILLED);
  OrbExtractor orb{OrbParams{}};
  Features a, b;
  orb.extract(grey, mask, a.keypoints, a.descriptors);
  orb.extract(textured_frame(0), cv::Mat(), b.keypoints, b.descriptors);  // buffers reused in between
  orb.extract(grey, mask, b.keypoints, b.descriptors);
  const Features c = extract(grey, mask);  // a fresh extractor
  for (const Features* other : {static_cast<const Features*>(&b), &c}) {
    ASSERT_EQ(a.keypoints.size(), other->keypoints.size());
    for (std::size_t i = 0; i < a.keypoints.size(); ++i) {
      const cv::KeyPoint &p = a.keypoints[i], &q = other->keypoints[i];
      ASSERT_TRUE(p.pt == q.pt && p.angle == q.angle && p.octave == q.octave && p.response == q.response &&
                  p.size == q.size)
          << "keypoint " << i;
    }
    ASSERT_EQ(a.descriptors.size(), other->descriptors.size());
    EXPECT_EQ(std::memcmp(a.descriptors.data, other->descriptors.data, a.descriptors.total()), 0);
  }
}

// Each level's corners and smoothing go to TBB as soon as the level is built, and each level is
// described as soon as its keypoints are chosen: with no helper at all (one thread) the caller
// does all of it itself, with the same bits, with and without a mask.
TEST(OrbExtractor, SameBitsWithoutAHelperThread) {
  const cv::Mat& grey = textured_frame(1);
  cv::Mat mask = cv::Mat::zeros(grey.size(), CV_8U);
  cv::circle(mask, {200, 180}, 70, cv::Scalar(1), cv::FILLED);
  for (const cv::Mat& m : {cv::Mat(), mask}) {
    SCOPED_TRACE(m.empty() ? "no mask" : "masked");
    OrbExtractor orb{OrbParams{}};
    Features parallel, alone;
    orb.detect(grey);
    orb.describe_detected(m, parallel.keypoints, parallel.descriptors);
    tbb::task_arena one_thread(1);
    one_thread.execute([&] {
      OrbExtractor own{OrbParams{}};
      own.detect(grey);
      own.describe_detected(m, alone.keypoints, alone.descriptors);
    });
    ASSERT_EQ(parallel.keypoints.size(), alone.keypoints.size());
    ASSERT_GT(parallel.keypoints.size(), 500u);
    for (std::size_t i = 0; i < parallel.keypoints.size(); ++i) {
      const cv::KeyPoint &p = parallel.keypoints[i], &q = alone.keypoints[i];
      ASSERT_TRUE(p.pt == q.pt && p.angle == q.angle && p.octave == q.octave && p.response == q.response)
          << "keypoint " << i;
    }
    ASSERT_EQ(parallel.descriptors.size(), alone.descriptors.size());
    EXPECT_EQ(std::memcmp(parallel.descriptors.data, alone.descriptors.data, parallel.descriptors.total()),
              0);
  }
}

TEST(OrbQuadtree, KeepsIsolatedCornersAndTheStrongestOfClusters) {
  std::vector<cv::KeyPoint> points;
  // 400 strong corners crowded into a 40x40 patch of a 400x400 area...
  for (int i = 0; i < 400; ++i)
    points.emplace_back(cv::Point2f(10.0f + i % 20 * 2.0f, 10.0f + i / 20 * 2.0f), 7.0f, -1.0f,
                        50.0f + i % 7);
  // ...and eight weak ones alone in distinct cells of a 4x4 split.
  const std::vector<cv::Point2f> lone{{150, 50},  {250, 50},  {350, 150}, {50, 250},
                                      {150, 250}, {250, 350}, {350, 350}, {350, 50}};
  for (const cv::Point2f& p : lone) points.emplace_back(p, 7.0f, -1.0f, 8.0f);
  lrd::features::QuadtreeDistributor q;
  const auto kept = q.select(points, cv::Rect2f(0, 0, 400, 400), 24);
  ASSERT_EQ(kept.size(), 24u);
  EXPECT_TRUE(std::is_sorted(kept.begin(), kept.end()));
  EXPECT_EQ(std::adjacent_find(kept.begin(), kept.end()), kept.end());
  for (int i = 400; i < 408; ++i)
    EXPECT_TRUE(std::binary_search(kept.begin(), kept.end(), i)) << "lone corner " << i;
  // Fewer points than asked: all of them; points outside the area: never.
  const std::vector<cv::KeyPoint> few(points.begin() + 400, points.end());
  EXPECT_EQ(q.select(few, cv::Rect2f(0, 0, 400, 400), 24).size(), 8u);
  EXPECT_TRUE(q.select(few, cv::Rect2f(0, 0, 40, 40), 24).empty());
  EXPECT_TRUE(q.select(points, cv::Rect2f(0, 0, 400, 400), 0).empty());
  // One per cell: asking for one point of the cluster gives its strongest.
  const std::vector<cv::KeyPoint> cluster(points.begin(), points.begin() + 400);
  const auto one = q.select(cluster, cv::Rect2f(0, 0, 400, 400), 1);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(cluster[one[0]].response, 56.0f);
}

TEST(OrbUndistortion, Tum1PixelsReturnToTheIdealPinhole) {
  const auto cam = lrd::camera::camera_preset("tum1");
  const KeypointUndistorter undistorter(cam);
  EXPECT_FALSE(undistorter.is_identity());
  // Ideal pixels, distorted with the Brown-Conrady model the TUM calibration uses.
  std::vector<cv::Point2f> ideal;
  for (float v : {5.0f, 60.0f, 240.0f, 420.0f, 475.0f}) {
    for (float u : {5.0f, 80.0f, 320.0f, 560.0f, 635.0f}) ideal.emplace_back(u, v);
  }
  const auto& d = cam.distortion;
  std::vector<cv::KeyPoint> distorted;
  for (const cv::Point2f& p : ideal) {
    const double x = (p.x - cam.cx) / cam.fx, y = (p.y - cam.cy) / cam.fy;
    const double r2 = x * x + y * y;
    const double radial = 1.0 + d.k1 * r2 + d.k2 * r2 * r2 + d.k3 * r2 * r2 * r2;
    const double xd = x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x);
    const double yd = y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y;
    distorted.emplace_back(
        cv::Point2f(static_cast<float>(cam.fx * xd + cam.cx), static_cast<float>(cam.fy * yd + cam.cy)),
        31.0f * 1.2f, 123.0f, 42.0f, 1);
  }
  const auto undistorted = undistorter.undistort(distorted);
  ASSERT_EQ(undistorted.size(), ideal.size());
  double moved = 0.0;
  for (std::size_t i = 0; i < ideal.size(); ++i) {
    EXPECT_NEAR(undistorted[i].pt.x, ideal[i].x, 0.05) << i;
    EXPECT_NEAR(undistorted[i].pt.y, ideal[i].y, 0.05) << i;
    EXPECT_EQ(undistorted[i].octave, 1);
    EXPECT_EQ(undistorted[i].angle, 123.0f);
    EXPECT_EQ(undistorted[i].response, 42.0f);
    moved = std::max(moved, cv::norm(distorted[i].pt - ideal[i]));
  }
  EXPECT_GT(moved, 5.0) << "the test points are distorted noticeably";
  const cv::Point2f one = undistorter.undistort(distorted[12].pt);
  EXPECT_NEAR(one.x, ideal[12].x, 0.05);
  const cv::Rect2f bounds = undistorter.undistorted_bounds();
  EXPECT_GT(bounds.width, 600.0f);
  EXPECT_GT(bounds.height, 440.0f);
}

TEST(OrbUndistortion, Tum3IsTheIdentity) {
  const KeypointUndistorter undistorter(lrd::camera::camera_preset("tum3"));
  EXPECT_TRUE(undistorter.is_identity());
  const std::vector<cv::KeyPoint> kps{cv::KeyPoint(10.25f, 400.5f, 31.0f, 7.0f, 20.0f, 0),
                                      cv::KeyPoint(633.0f, 2.0f, 44.6f, 300.0f, 9.0f, 2)};
  const auto out = undistorter.undistort(kps);
  ASSERT_EQ(out.size(), 2u);
  for (std::size_t i = 0; i < kps.size(); ++i) {
    EXPECT_EQ(out[i].pt, kps[i].pt);
    EXPECT_EQ(out[i].octave, kps[i].octave);
  }
  EXPECT_EQ(undistorter.undistorted_bounds(), cv::Rect2f(0.0f, 0.0f, 640.0f, 480.0f));
}

// The smoother steered BRIEF samples from: whichever copy of its loops runs on this CPU (AVX2 or
// the SSE2 baseline), the result is the fixed-point 7x7 filter of its contract, pixel for pixel,
// on widths that leave every kind of tail for the vector loops.
TEST(GaussianSmoother, EveryPixelIsTheFixedPointFilterOfItsContract) {
  constexpr auto& taps = lrd::features::GaussianSmoother::kTaps;
  std::mt19937 rng(23);
  std::uniform_int_distribution<int> value(0, 255);
  lrd::features::GaussianSmoother smoother;
  for (const cv::Size size : {cv::Size(640, 480), cv::Size(37, 29), cv::Size(7, 7), cv::Size(101, 8)}) {
    SCOPED_TRACE(size);
    cv::Mat src(size, CV_8UC1);
    for (int v = 0; v < src.rows; ++v)
      for (int u = 0; u < src.cols; ++u) src.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>(value(rng));
    cv::Mat dst;
    smoother.smooth(src, dst);
    ASSERT_EQ(dst.type(), CV_8UC1);
    ASSERT_EQ(dst.size(), src.size());
    int wrong = 0;
    for (int v = 0; v < src.rows; ++v)
      for (int u = 0; u < src.cols; ++u) {
        int expected = src.at<std::uint8_t>(v, u);  // the 3-pixel frame is copied
        if (v >= 3 && v < src.rows - 3 && u >= 3 && u < src.cols - 3) {
          unsigned sum = 0;
          for (int du = -3; du <= 3; ++du) {
            unsigned column = 0;  // vertical pass first, rounded to 8 bits
            for (int dv = -3; dv <= 3; ++dv)
              column += static_cast<unsigned>(taps[std::abs(dv)]) * src.at<std::uint8_t>(v + dv, u + du);
            sum += static_cast<unsigned>(taps[std::abs(du)]) * ((column + 128u) >> 8);
          }
          expected = static_cast<int>((sum + 128u) >> 8);
        }
        wrong += dst.at<std::uint8_t>(v, u) != expected;
      }
    EXPECT_EQ(wrong, 0);
  }
}

// build_level(i) in turn after set_base() is build(): the extractor starts on a level while the
// next is made.
TEST(ImagePyramid, LevelByLevelIsTheWholeBuild) {
  const cv::Mat& grey = textured_frame(0);
  lrd::features::ImagePyramid whole(8, 1.2f), stepwise(8, 1.2f);
  whole.build(grey);
  stepwise.set_base(grey);
  for (int i = 1; i < stepwise.levels(); ++i) stepwise.build_level(i);
  for (int i = 0; i < whole.levels(); ++i) {
    SCOPED_TRACE(i);
    ASSERT_EQ(whole.level(i).size(), stepwise.level(i).size());
    EXPECT_EQ(cv::norm(whole.level(i), stepwise.level(i), cv::NORM_INF), 0.0);
    EXPECT_EQ(whole.to_base(i, 10.0f, 20.0f), stepwise.to_base(i, 10.0f, 20.0f));
  }
  EXPECT_EQ(whole.level(1).size(), cv::Size(533, 400));  // 640x480 / 1.2, rounded
  EXPECT_THROW(stepwise.build_level(0), cv::Exception);
  EXPECT_THROW(stepwise.build_level(8), cv::Exception);
}
