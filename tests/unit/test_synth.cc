// The synthetic benchmark: every preset renders; geometry is consistent with the ground-truth
// poses; masks cover exactly the actors; output is deterministic; the TUM layout reads back.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "lrd/io/trajectory.h"
#include "lrd/io/tum_sequence.h"
#include "lrd/synth/camera_motion.h"
#include "lrd/synth/sequence_writer.h"
#include "lrd/synth/synthetic_sequence.h"
#include "lrd/util/error.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using lrd::synth::SyntheticSequence;
using lrd::synth::SynthFrame;
using lrd::synth::SynthOptions;

namespace {

SynthOptions options(const std::string& preset, int frames, std::uint64_t seed = 1) {
  SynthOptions o;
  o.preset = preset;
  o.frames = frames;
  o.seed = seed;
  return o;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

TEST(SynthPresets, EveryPresetRendersPlausibleFrames) {
  // One texture library for all presets: loading it is most of a preset's cost under ASan.
  const auto textures = SyntheticSequence::load_textures();
  for (const auto& spec : lrd::synth::preset_specs()) {
    SCOPED_TRACE(spec.name);
    const SyntheticSequence seq(options(spec.name, 301), textures);
    EXPECT_EQ(seq.size(), 301);
    double dynamic = 0.0;
    for (int i : {0, 150, 300}) {
      const SynthFrame f = seq.render(i);
      ASSERT_EQ(f.rgb.type(), CV_8UC3);
      ASSERT_EQ(f.rgb.size(), cv::Size(640, 480));
      ASSERT_EQ(f.depth.type(), CV_16U);
      ASSERT_EQ(f.mask.type(), CV_8U);
      // Indoors at 1-4.5 m: most pixels carry depth, and none beyond the sensor's range.
      EXPECT_GT(cv::countNonZero(f.depth), 0.6 * f.depth.total());
      double max_depth;
      cv::minMaxLoc(f.depth, nullptr, &max_depth);
      EXPECT_LE(max_depth, 4.5 * 5000.0 + 1.0);
      // Textured enough for ORB: FAST at ORB's initial threshold finds plenty of corners.
      cv::Mat grey;
      cv::cvtColor(f.rgb, grey, cv::COLOR_BGR2GRAY);
      std::vector<cv::KeyPoint> corners;
      cv::FAST(grey, corners, 20);
      EXPECT_GT(corners.size(), 300u);
      dynamic += cv::countNonZero(f.mask) / static_cast<double>(f.mask.total()) / 3.0;
    }
    if (spec.cast == lrd::synth::Cast::kNobody) {
      EXPECT_EQ(dynamic, 0.0);
    } else {
      EXPECT_GT(dynamic, 0.01);
    }
  }
}

TEST(SynthPresets, UnknownPresetNamesTheValidOnes) {
  try {
    (void)lrd::synth::find_preset("walking_fast");
    FAIL();
  } catch (const lrd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("walking_fast"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("walking_halfsphere"), std::string::npos);
  }
}

TEST(SynthPresets, TheLongPresetToursTheRoomForTwelveMinutesAndRevisits) {
  // The long preset (bench/results/scale.md): >= 20,000 frames, laps with revisits, people walking,
  // a hand-held pace.
  const SyntheticSequence seq(options("walking_long", -1));
  EXPECT_GE(seq.size(), 20000);
  EXPECT_GT(seq.actor_descriptions().size(), 1u);
  const int lap = static_cast<int>(lrd::synth::CameraMotion::kTourLap * seq.camera().fps);
  double length = 0.0;
  Eigen::Vector3d previous = seq.pose(0).translation();
  for (int i = 30; i < seq.size(); i += 30) {  // once a second
    const Eigen::Isometry3d T = seq.pose(i);
    length += (T.translation() - previous).norm();
    previous = T.translation();
    // Inside the walkers' rectangle and clear of the furniture, at a standing person's height.
    EXPECT_GT(T.translation().x(), 1.7);
    EXPECT_LT(T.translation().x(), 3.7);
    EXPECT_NEAR(T.translation().z(), 1.35, 0.17);
  }
  const double seconds = seq.size() / seq.camera().fps;
  EXPECT_GT(length / seconds, 0.12);  // m/s, TUM fr3 walking: 0.1-0.4
  EXPECT_LT(length / seconds, 0.35);
  // A lap later the camera is back within 0.35 m of where it was, looking the same way:
  // a revisit (a loop to close) at every lap.
  for (int i = 0; i + lap < seq.size(); i += 7 * lap) {
    const Eigen::Isometry3d a = seq.pose(i), b = seq.pose(i + lap);
    EXPECT_LT((a.translation() - b.translation()).norm(), 0.35) << "frame " << i;
    EXPECT_GT(a.rotation().col(2).dot(b.rotation().col(2)), 0.97) << "frame " << i;
  }
  // A prefix is the same path (run --synth walking_long --frames N).
  const SyntheticSequence prefix(options("walking_long", 900));
  EXPECT_TRUE(prefix.pose(899).isApprox(seq.pose(899), 1e-12));
}

TEST(SynthPresets, TheCirclePresetRepeatsOneLapWithTheLongPresetsPeople) {
  // walking_circle's camera: the same circle for 12 minutes, so the space explored stops growing
  // after the first lap (bench_scale compares the keyframes after lap 2 with those at the end).
  const SyntheticSequence seq(options("walking_circle", -1));
  EXPECT_GE(seq.size(), 20000);
  EXPECT_EQ(seq.actor_descriptions(), SyntheticSequence(options("walking_long", 30)).actor_descriptions());
  const int lap = static_cast<int>(lrd::synth::CameraMotion::kTourLap * seq.camera().fps);
  for (int i = 0; i + lap < seq.size(); i += 5 * lap + 97) {
    const Eigen::Isometry3d a = seq.pose(i), b = seq.pose(i + lap);
    EXPECT_LT((a.translation() - b.translation()).norm(), 0.03) << "frame " << i;  // the tremor only
    EXPECT_GT(a.rotation().col(2).dot(b.rotation().col(2)), 0.99) << "frame " << i;
    EXPECT_NEAR((a.translation() - Eigen::Vector3d(2.7, 2.5, 1.35)).head<2>().norm(), 0.65, 0.03);
  }
}

TEST(SynthPresets, WalkingPeopleOftenCoverATwentyToFiftyPercent) {
  // TUM's walking sequences have people covering large parts of the view; ours must too, or the
  // dynamic-scene results would be measured on an easy benchmark.
  const SyntheticSequence seq(options("walking_xyz", -1));
  std::vector<double> coverage;
  for (int i = 0; i < seq.size(); i += 30) {
    const cv::Mat mask = seq.render(i).mask;
    coverage.push_back(cv::countNonZero(mask) / static_cast<double>(mask.total()));
  }
  const auto in_band =
      std::count_if(coverage.begin(), coverage.end(), [](double c) { return c >= 0.2 && c <= 0.5; });
  EXPECT_GE(static_cast<double>(in_band) / coverage.size(), 0.25);
  EXPECT_GT(median(coverage), 0.1);
}

TEST(SynthGeometry, StaticPointsReprojectWithGroundTruthPoses) {
  const SyntheticSequence seq(options("walking_xyz", 40));
  const auto& cam = seq.camera();
  const SynthFrame a = seq.render(5), b = seq.render(35);
  const Eigen::Isometry3d T_ba = b.pose.inverse() * a.pose;
  ASSERT_GT(T_ba.translation().norm(), 0.05) << "the camera must have moved for this test to mean anything";
  cv::Mat grey_a, grey_b;
  cv::cvtColor(a.static_rgb, grey_a, cv::COLOR_BGR2GRAY);
  cv::cvtColor(b.static_rgb, grey_b, cv::COLOR_BGR2GRAY);
  std::vector<double> rel_depth_err, intensity_err;
  for (int v = 4; v < 476; v += 6) {
    for (int u = 4; u < 636; u += 6) {
      const double za = a.static_depth.at<std::uint16_t>(v, u) / cam.depth_map_factor;
      if (za <= 0) continue;
      const Eigen::Vector3d pb = T_ba * cam.unproject(u, v, za);
      const Eigen::Vector2d uv = cam.project(pb);
      const int ub = static_cast<int>(std::lround(uv.x())), vb = static_cast<int>(std::lround(uv.y()));
      if (ub < 2 || vb < 2 || ub > 637 || vb > 477) continue;
      const double zb = b.static_depth.at<std::uint16_t>(vb, ub) / cam.depth_map_factor;
      if (zb <= 0 || std::abs(zb - pb.z()) > 0.2 * pb.z()) continue;  // occlusion boundary
      rel_depth_err.push_back(std::abs(zb - pb.z()) / (pb.z() * pb.z()));
      cv::Mat patch;
      cv::getRectSubPix(grey_b, {1, 1}, cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y())),
                        patch);
      intensity_err.push_back(std::abs(patch.at<uchar>(0, 0) - static_cast<double>(grey_a.at<uchar>(v, u))));
    }
  }
  ASSERT_GT(rel_depth_err.size(), 3000u);
  // Kinect-like noise: sigma_z ~ 0.002-0.003 z^2 from disparity noise and 1/8 px quantisation.
  EXPECT_LT(median(rel_depth_err), 0.006);
  // Same surface point, same colour up to sensor noise, blur and shading (flat per triangle).
  EXPECT_LT(median(intensity_err), 12.0);
}

TEST(SynthMasks, MaskCoversExactlyTheActors) {
  const SyntheticSequence seq(options("walking_pushed", 301));
  bool saw_person = false, saw_object = false;
  for (int i : {60, 150, 300}) {
    SCOPED_TRACE(i);
    const SynthFrame f = seq.render(i);
    saw_person |= cv::countNonZero(f.mask == 1) > 0;
    saw_object |= cv::countNonZero(f.mask == 2) > 0;
    // Away from actors (beyond the optics blur), the image is exactly the actor-free one.
    cv::Mat near_actor;
    cv::dilate(f.mask > 0, near_actor, cv::Mat::ones(7, 7, CV_8U));
    cv::Mat diff;
    cv::absdiff(f.rgb, f.static_rgb, diff);
    cv::cvtColor(diff, diff, cv::COLOR_BGR2GRAY);
    EXPECT_EQ(cv::countNonZero(diff & ~near_actor), 0);
    // Outside the mask, wherever both have depth, it is the static depth (holes differ: the actors
    // cast projector shadows and change which pixels sit next to a depth edge).
    int outside_mismatch = 0, inside_total = 0, inside_in_front = 0;
    for (int v = 0; v < 480; ++v) {
      for (int u = 0; u < 640; ++u) {
        const int d = f.depth.at<std::uint16_t>(v, u), s = f.static_depth.at<std::uint16_t>(v, u);
        if (f.mask.at<uchar>(v, u) == 0) {
          outside_mismatch += (d != 0 && s != 0 && d != s);
        } else if (d != 0 && s != 0) {
          ++inside_total;
          // In front of the static scene, up to sensor noise (feet on the floor, a chair at the desk).
          inside_in_front += d < s + std::max(100, s / 50);
        }
      }
    }
    EXPECT_EQ(outside_mismatch, 0);
    // Inside the mask, every valid pixel is an actor standing in front of the static scene.
    if (inside_total > 0) {
      EXPECT_GE(inside_in_front, 0.995 * inside_total);
    }
  }
  EXPECT_TRUE(saw_person);
  EXPECT_TRUE(saw_object) << "walking_pushed must show the pushed chair or the carried box";
}

TEST(SynthSensor, DepthNoiseGrowsWithDistanceAndRangeIsLimited) {
  const auto cam = lrd::camera::camera_preset("tum3");
  const lrd::synth::SensorModel sensor(cam, {}, 7);
  lrd::synth::RenderBuffers ideal;
  ideal.depth = cv::Mat(480, 640, CV_32F, cv::Scalar(1.0f));
  ideal.depth(cv::Rect(0, 160, 640, 160)).setTo(3.0f);
  ideal.depth(cv::Rect(0, 320, 640, 160)).setTo(5.0f);
  ideal.incidence = cv::Mat(480, 640, CV_32F, cv::Scalar(1.0f));
  ideal.incidence(cv::Rect(600, 0, 40, 480)).setTo(0.05f);  // grazing
  const cv::Mat d = sensor.depth_image(ideal, 0);
  auto band_stats = [&](int y0, double z, double& mean_abs, double& valid) {
    double sum = 0;
    int n = 0, total = 0;
    for (int v = y0 + 5; v < y0 + 155; ++v)
      for (int u = 0; u < 590; ++u, ++total) {
        const double m = d.at<std::uint16_t>(v, u) / 5000.0;
        if (m > 0) {
          sum += std::abs(m - z);
          ++n;
        }
      }
    mean_abs = n ? sum / n : 0.0;
    valid = static_cast<double>(n) / total;
  };
  double e1, v1, e3, v3, e5, v5;
  band_stats(0, 1.0, e1, v1);
  band_stats(160, 3.0, e3, v3);
  band_stats(320, 5.0, e5, v5);
  EXPECT_GT(v1, 0.99);
  EXPECT_GT(v3, 0.99);
  EXPECT_EQ(v5, 0.0) << "beyond the 4.5 m working range there is no depth";
  EXPECT_GT(e1, 0.0005);
  EXPECT_LT(e1, 0.005);
  // Quadratic growth: 9x the distance squared; allow for quantisation effects.
  EXPECT_GT(e3 / e1, 5.0);
  EXPECT_LT(e3 / e1, 14.0);
  EXPECT_EQ(cv::countNonZero(d(cv::Rect(600, 0, 40, 480))), 0) << "grazing incidence gives holes";
}

TEST(SynthSensor, ProjectorShadowBesideForegroundEdge) {
  const auto cam = lrd::camera::camera_preset("tum3");
  lrd::synth::SensorParams p;
  p.edge_dropout = 0.0;
  const lrd::synth::SensorModel sensor(cam, p, 3);
  lrd::synth::RenderBuffers ideal;
  ideal.depth = cv::Mat(480, 640, CV_32F, cv::Scalar(3.0f));
  ideal.depth(cv::Rect(200, 100, 100, 200)).setTo(1.0f);
  ideal.incidence = cv::Mat(480, 640, CV_32F, cv::Scalar(1.0f));
  const cv::Mat d = sensor.depth_image(ideal, 0);
  // Shadow width = f b (1/z_fg - 1/z_bg) = 535.4 * 0.075 * (1 - 1/3) = 26.8 px, right of the block.
  const int row = 200;
  int holes = 0;
  for (int u = 300; u < 340; ++u) holes += d.at<std::uint16_t>(row, u) == 0;
  EXPECT_NEAR(holes, 26.8, 1.5);
  EXPECT_GT(d.at<std::uint16_t>(row, 199), 0) << "no shadow on the left side";
}

TEST(SynthDeterminism, SameSeedSameBytesDifferentSeedDifferentNoise) {
  const SyntheticSequence a(options("walking_rpy", 20, 5)), b(options("walking_rpy", 20, 5)),
      c(options("walking_rpy", 20, 6));
  const SynthFrame fa = a.render(17), fb = b.render(17), fc = c.render(17);
  EXPECT_EQ(cv::norm(fa.rgb, fb.rgb, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(fa.depth, fb.depth, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(fa.mask, fb.mask, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(fa.rgb, fc.rgb, cv::NORM_L1), 0.0);
}

TEST(SynthWriter, WritesTumLayoutDeterministicallyAndReadsBack) {
  const SyntheticSequence seq(options("walking_halfsphere", 6, 3));
  const lrd::test::TempDir t1("synth_w1"), t2("synth_w2");
  const fs::path d1 = t1.path(), d2 = t2.path();
  (void)lrd::synth::write_sequence(seq, d1);
  (void)lrd::synth::write_sequence(seq, d2);
  std::size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(d1)) {
    if (!e.is_regular_file()) continue;
    ++files;
    const fs::path rel = fs::relative(e.path(), d1);
    EXPECT_EQ(lrd::test::TempDir::read(e.path()), lrd::test::TempDir::read(d2 / rel)) << rel;
  }
  EXPECT_EQ(files,
            6u * 5u + 7u);  // 5 images per frame; rgb/depth/associations, gt, settings, json, scene.ply
  // The project's own TUM reader associates it back frame for frame.
  const auto tum = lrd::io::TumSequence::open(d1);
  ASSERT_EQ(tum.size(), 6u);
  ASSERT_TRUE(tum.groundtruth_path().has_value());
  const auto gt = lrd::io::read_trajectory_tum(*tum.groundtruth_path());
  ASSERT_EQ(gt.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_NEAR(tum.entry(i).timestamp, seq.timestamp(static_cast<int>(i)), 1e-6);
    EXPECT_TRUE(gt[i].pose.isApprox(seq.pose(static_cast<int>(i)), 1e-8));
  }
  const auto frame = tum.load_rgbd(3, 5000.0);
  const SynthFrame f = seq.render(3);
  cv::Mat expected;
  f.depth.convertTo(expected, CV_32F, 1.0 / 5000.0);
  EXPECT_LT(cv::norm(frame.depth, expected, cv::NORM_INF), 1e-6);
}

// scene.ply: samples on the static surfaces in the ground-truth world frame. Seen from a frame,
// none may float in front of the surface the static depth image shows (free space), and many
// lie on it.
TEST(SynthScene, SamplesLieOnTheStaticSurfaces) {
  const SyntheticSequence seq(options("walking_xyz", 3, 1));
  const lrd::dense::PointCloud scene = seq.scene_samples();
  ASSERT_GT(scene.size(), 100000u);
  ASSERT_EQ(scene.colours.size(), scene.size());
  const SynthFrame f = seq.render(0);
  const Eigen::Isometry3f T_cw = f.pose.inverse().cast<float>();
  const auto& cam = seq.camera();
  int on_surface = 0, in_free_space = 0;
  for (const Eigen::Vector3f& p : scene.points) {
    EXPECT_TRUE(p.x() > -0.01f && p.x() < 6.01f && p.y() > -0.01f && p.y() < 5.01f && p.z() > -0.01f &&
                p.z() < 3.01f)
        << p.transpose();
    const Eigen::Vector3f c = T_cw * p;
    if (c.z() < 0.3f) continue;
    const int u = static_cast<int>(std::lround(cam.fx * c.x() / c.z() + cam.cx));
    const int v = static_cast<int>(std::lround(cam.fy * c.y() / c.z() + cam.cy));
    if (u < 0 || v < 0 || u >= cam.width || v >= cam.height) continue;
    const double z = f.static_depth.at<std::uint16_t>(v, u) / cam.depth_map_factor;
    if (z <= 0) continue;
    if (std::abs(z - c.z()) < 0.03 + 0.02 * z)
      ++on_surface;
    else if (c.z() < z - 0.15)
      ++in_free_space;
  }
  EXPECT_GT(on_surface, 10000);
  EXPECT_LT(in_free_space, on_surface / 200);
}
