// The `tum` realism profile (docs/synthetic-benchmark.md): each effect on hand-made images with a
// known answer, and a rendered frame whose static view, determinism and ground truth keep their
// contracts.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "lrd/eval/motion_statistics.h"
#include "lrd/synth/realistic_camera.h"
#include "lrd/synth/synthetic_sequence.h"
#include "lrd/util/error.h"

using lrd::synth::NoiseTable;
using lrd::synth::RealismParams;
using lrd::synth::RealisticCamera;

namespace {

const lrd::camera::PinholeCamera& camera() {
  static const auto cam = lrd::camera::camera_preset("tum3");
  return cam;
}

const NoiseTable& noise() {
  static const NoiseTable table(5);
  return table;
}

// Only the named effects on, nothing else.
RealismParams only(std::initializer_list<bool RealismParams::*> effects) {
  RealismParams p;
  p.profile = "tum";
  for (auto e : effects) p.*e = true;
  return p;
}

double mean_grey(const cv::Mat& bgr) {
  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  return cv::mean(grey)[0];
}

}  // namespace

TEST(Realism, ProfilesAndEffectSwitches) {
  EXPECT_TRUE(lrd::synth::realism_profile("clean").is_clean());
  RealismParams tum = lrd::synth::realism_profile("tum");
  EXPECT_FALSE(tum.is_clean());
  EXPECT_TRUE(tum.rolling_shutter && tum.bayer && tum.gt_mocap_rate);
  lrd::synth::disable_realism_effects(tum, "rolling_shutter,bayer");
  EXPECT_FALSE(tum.rolling_shutter);
  EXPECT_FALSE(tum.bayer);
  EXPECT_TRUE(tum.motion_blur);
  std::string all;
  for (const auto& e : lrd::synth::realism_effects()) all += (all.empty() ? "" : ",") + e;
  lrd::synth::disable_realism_effects(tum, all);
  EXPECT_TRUE(tum.is_clean());
  EXPECT_THROW(lrd::synth::realism_profile("kinect2"), lrd::Error);
  try {
    lrd::synth::disable_realism_effects(tum, "bayer,blurr");
    FAIL() << "an unknown effect was accepted";
  } catch (const lrd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown effect 'blurr'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("rolling_shutter"), std::string::npos) << e.what();
  }
}

TEST(Realism, TheUsersCalibrationIsALittleOff) {
  const RealismParams tum = lrd::synth::realism_profile("tum");
  const auto cal = lrd::synth::calibrated_camera(camera(), tum);
  EXPECT_NEAR(cal.fx / camera().fx, 1.0 + tum.focal_error_x, 1e-12);
  EXPECT_NEAR(cal.fy / camera().fy, 1.0 + tum.focal_error_y, 1e-12);
  EXPECT_NEAR(cal.distortion.k1, tum.rendered_distortion.k1 + tum.k1_error, 1e-12);
  EXPECT_EQ(cal.distortion.k2, tum.rendered_distortion.k2);
  // A rolling-shutter calibration knows the readout time; without the effect there is none.
  EXPECT_EQ(cal.readout_time, tum.readout_time);
  RealismParams global = tum;
  lrd::synth::disable_realism_effects(global, "rolling_shutter");
  EXPECT_EQ(lrd::synth::calibrated_camera(camera(), global).readout_time, 0.0);
  const auto clean = lrd::synth::calibrated_camera(camera(), RealismParams{});
  EXPECT_EQ(clean.fx, camera().fx);
  EXPECT_TRUE(clean.distortion.is_zero());
  EXPECT_EQ(clean.readout_time, 0.0);
}

TEST(Realism, AutoExposureLengthensForDarkViewsThenRaisesTheGain) {
  const RealisticCamera cam(camera(), only({&RealismParams::auto_exposure}), 0.6, noise());
  const cv::Mat bright(480, 640, CV_8UC3, cv::Scalar::all(200)), mid(480, 640, CV_8UC3, cv::Scalar::all(90)),
      dark(480, 640, CV_8UC3, cv::Scalar::all(25));
  const auto eb = cam.expose(bright), em = cam.expose(mid), ed = cam.expose(dark);
  EXPECT_LT(eb.time, em.time);
  EXPECT_DOUBLE_EQ(eb.gain, 1.0);
  EXPECT_DOUBLE_EQ(em.gain, 1.0);
  EXPECT_DOUBLE_EQ(ed.time, cam.params().max_exposure);
  EXPECT_GT(ed.gain, 1.0);
  // Where neither limit binds, the developed image sits at the target level.
  EXPECT_NEAR(mean_grey(cam.develop(cam.linear(mid), em, 0)), cam.params().target_grey, 2.0);
  EXPECT_NEAR(mean_grey(cam.develop(cam.linear(bright), eb, 0)), cam.params().target_grey, 2.0);
}

TEST(Realism, WhiteBalancePullsAColouredViewPartWayToGrey) {
  const RealisticCamera cam(camera(), only({&RealismParams::white_balance}), 0.6, noise());
  const cv::Mat reddish(480, 640, CV_8UC3, cv::Scalar(80, 100, 160));
  const auto e = cam.expose(reddish);
  EXPECT_GT(e.white_balance[0], 1.0);  // blue up
  EXPECT_LT(e.white_balance[2], 1.0);  // red down
  const cv::Scalar out = cv::mean(cam.develop(cam.linear(reddish), e, 0));
  EXPECT_GT(out[2] - out[0], 20.0);  // still reddish: only part way
  EXPECT_LT(out[2] - out[0], 160.0 - 80.0);
}

TEST(Realism, RollingShutterRowsSpanTheReadoutAndBlurSpansTheExposure) {
  const RealisticCamera cam(camera(), only({&RealismParams::rolling_shutter, &RealismParams::motion_blur}),
                            0.6, noise());
  RealisticCamera::Exposure e;
  e.time = 0.02;
  const double t = 3.0;
  const auto plan = cam.shutter(t, e);
  ASSERT_GE(plan.times.size(), 2u);
  EXPECT_NEAR(plan.times.front(), t - 0.5 * (0.028 + 0.02), 1e-12);
  EXPECT_NEAR(plan.times.back(), t + 0.5 * (0.028 + 0.02), 1e-12);
  auto centroid = [&](int row) {
    double c = 0.0, sum = 0.0;
    for (std::size_t k = 0; k < plan.times.size(); ++k) {
      c += plan.row_weights.at<float>(row, static_cast<int>(k)) * plan.times[k];
      sum += plan.row_weights.at<float>(row, static_cast<int>(k));
    }
    EXPECT_NEAR(sum, 1.0, 1e-5);
    return c / sum;
  };
  EXPECT_NEAR(centroid(0), t - 0.014, 1e-4);
  EXPECT_NEAR(centroid(239), t + 0.028 * (239.0 / 479.0 - 0.5), 1e-4);
  EXPECT_NEAR(centroid(479), t + 0.014, 1e-4);

  // A bright bar moving right at 1000 px/s: integrated, its centre is 28 px further right on the
  // last row than on the first (rolling shutter), and it is 20 px wider than drawn (blur).
  std::vector<cv::Mat> renders;
  for (double tk : plan.times) {
    cv::Mat img(480, 640, CV_8UC3, cv::Scalar::all(0));
    const double x = 300.0 + 1000.0 * (tk - t);
    cv::rectangle(img, cv::Point(static_cast<int>(std::lround(x)) - 5, 0),
                  cv::Point(static_cast<int>(std::lround(x)) + 5, 479), cv::Scalar::all(255), cv::FILLED);
    renders.push_back(img);
  }
  const cv::Mat light = cam.integrate(renders, plan);
  auto row_centre = [&](int y, double* width) {
    double c = 0.0, sum = 0.0;
    for (int x = 0; x < light.cols; ++x) {
      const double v = light.at<cv::Vec3f>(y, x)[1];
      c += v * x;
      sum += v;
    }
    *width = sum;  // the bar's light in the row: 11 px whatever the blur
    return c / sum;
  };
  double w0 = 0.0, w1 = 0.0;
  EXPECT_NEAR(row_centre(479, &w1) - row_centre(0, &w0), 28.0, 1.5);
  EXPECT_NEAR(w0, 11.0, 0.5);
  // The blur: the row's light spread as an 11 px box convolved with a 20 px one (variance
  // (11^2 - 1)/12 + 20^2/12), where the bar alone would be 3.2 px.
  double mean = 0.0, square = 0.0, sum = 0.0;
  for (int x = 0; x < light.cols; ++x) {
    const double v = light.at<cv::Vec3f>(240, x)[1];
    mean += v * x;
    square += v * x * x;
    sum += v;
  }
  mean /= sum;
  EXPECT_NEAR(std::sqrt(square / sum - mean * mean), std::sqrt(10.0 + 400.0 / 12.0), 0.7);
}

TEST(Realism, AFlatColourSurvivesTheBayerMosaic) {
  const RealisticCamera cam(camera(), only({&RealismParams::bayer}), 0.6, noise());
  for (const cv::Scalar& colour :
       {cv::Scalar(30, 60, 200), cv::Scalar(200, 90, 40), cv::Scalar(50, 180, 70)}) {
    const cv::Mat flat(480, 640, CV_8UC3, colour);
    const cv::Mat out = cam.develop(cam.linear(flat), RealisticCamera::Exposure{0.01, 1.0, {1, 1, 1}}, 0);
    const cv::Scalar m = cv::mean(out(cv::Rect(10, 10, 620, 460)));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(m[c], colour[c], 2.0) << "channel " << c;
  }
}

TEST(Realism, SensorNoiseIsShotPlusReadNoise) {
  RealismParams p = only({&RealismParams::sensor_noise});
  const RealisticCamera cam(camera(), p, 0.0, noise());
  for (const int level : {40, 120, 220}) {
    const cv::Mat flat(480, 640, CV_8UC3, cv::Scalar::all(level));
    const cv::Mat out = cam.develop(cam.linear(flat), RealisticCamera::Exposure{0.01, 1.0, {1, 1, 1}}, 3);
    cv::Scalar mean, stddev;
    cv::meanStdDev(out.reshape(1), mean, stddev);
    // Predicted: electrons e = light x full well, sigma_e = sqrt(e + read^2), through the gamma.
    const double light = std::pow(level / 255.0, 2.2), e = light * p.full_well_electrons;
    const double sigma_e = std::sqrt(e + p.read_noise_electrons * p.read_noise_electrons);
    const double slope = 255.0 / 2.2 * std::pow(light, 1.0 / 2.2 - 1.0) / p.full_well_electrons;
    EXPECT_NEAR(stddev[0], sigma_e * slope, 0.15 * sigma_e * slope) << "level " << level;
    EXPECT_NEAR(mean[0], level, 1.0);
  }
}

TEST(Realism, VignettingDarkensTheCorners) {
  const RealisticCamera cam(camera(), only({&RealismParams::vignetting}), 0.6, noise());
  const cv::Mat flat(480, 640, CV_8UC3, cv::Scalar::all(150));
  const cv::Mat out = cam.develop(cam.linear(flat), RealisticCamera::Exposure{0.01, 1.0, {1, 1, 1}}, 0);
  const double centre = out.at<cv::Vec3b>(248, 320)[1], corner = out.at<cv::Vec3b>(2, 2)[1];
  EXPECT_NEAR(centre, 150.0, 1.0);
  // 20 % less light at the farthest corner; through the gamma: (0.8)^(1/2.2) of the level.
  EXPECT_NEAR(corner, 150.0 * std::pow(1.0 - 0.2 * 0.98, 1 / 2.2), 2.0);
}

TEST(Realism, DistortionMovesPixelsAsTheLensModelSays) {
  const RealismParams p = only({&RealismParams::distortion});
  const RealisticCamera cam(camera(), p, 0.6, noise());
  const auto& c = camera();
  for (const cv::Point2f& ideal : {cv::Point2f(60, 50), cv::Point2f(600, 420), cv::Point2f(330, 250)}) {
    cv::Mat labels(480, 640, CV_8U, cv::Scalar(0));
    cv::rectangle(labels, cv::Point(static_cast<int>(ideal.x) - 1, static_cast<int>(ideal.y) - 1),
                  cv::Point(static_cast<int>(ideal.x) + 1, static_cast<int>(ideal.y) + 1), cv::Scalar(1),
                  cv::FILLED);
    const cv::Mat warped = cam.warp_labels(labels);
    const cv::Moments m = cv::moments(warped, true);
    ASSERT_GT(m.m00, 0.0);
    // Where the model puts the ideal point.
    const std::vector<cv::Point3d> ray = {{(ideal.x - c.cx) / c.fx, (ideal.y - c.cy) / c.fy, 1.0}};
    std::vector<cv::Point2d> projected;
    const auto& d = p.rendered_distortion;
    cv::projectPoints(ray, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0),
                      cv::Matx33d(c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1),
                      cv::Matx<double, 1, 5>(d.k1, d.k2, d.p1, d.p2, d.k3), projected);
    EXPECT_NEAR(m.m10 / m.m00, projected[0].x, 1.0);
    EXPECT_NEAR(m.m01 / m.m00, projected[0].y, 1.0);
  }
}

TEST(Realism, DepthIsRegisteredWithAnErrorInWholeMillimetresWithSpeckleHoles) {
  RealismParams p = only(
      {&RealismParams::depth_registration, &RealismParams::depth_millimetres, &RealismParams::speckle_holes});
  p.registration_error_x = 2.0;
  p.registration_error_y = -1.0;
  const RealisticCamera cam(camera(), p, 0.6, noise());
  cv::Mat depth(480, 640, CV_16U, cv::Scalar(10003));
  depth(cv::Rect(320, 0, 320, 480)).setTo(20001);
  const cv::Mat out = cam.register_depth(depth, 4, 5000.0);
  int holes = 0;
  for (int y = 1; y < 479; ++y)
    for (int x = 0; x < 638; ++x) {
      const auto v = out.at<std::uint16_t>(y, x);
      if (v == 0) {
        ++holes;
        continue;
      }
      EXPECT_EQ(v % 5, 0) << "not whole millimetres at " << x << "," << y;
      // Colour pixel x shows depth pixel x + 2: the step appears at x = 318.
      EXPECT_EQ(v, x + 2 < 320 ? 10005 : 20000) << x << "," << y;
    }
  const double hole_share = static_cast<double>(holes) / (478.0 * 638.0);
  // Each seed a 3 x 3 hole: about 9 x the seed rate, less where holes overlap.
  EXPECT_GT(hole_share, 6.0 * p.speckle_hole_rate);
  EXPECT_LT(hole_share, 11.0 * p.speckle_hole_rate);
}

TEST(Realism, ARenderedTumFrameKeepsTheStaticViewAndIsDeterministic) {
  lrd::synth::SynthOptions o;
  o.preset = "walking_xyz";
  o.frames = 40;
  o.realism = lrd::synth::realism_profile("tum");
  const lrd::synth::SyntheticSequence seq(o);
  const auto a = seq.render(30), b = seq.render(30);
  ASSERT_EQ(a.rgb.type(), CV_8UC3);
  EXPECT_EQ(cv::norm(a.rgb, b.rgb, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.depth, b.depth, cv::NORM_INF), 0.0);
  // Away from the people (and the blur of their motion), the actor-free view is the same image:
  // same exposure, white balance and noise.
  cv::Mat near_people;
  cv::dilate(a.mask > 0, near_people, cv::Mat::ones(41, 41, CV_8U));
  cv::Mat diff;
  cv::absdiff(a.rgb, a.static_rgb, diff);
  cv::Mat differs;
  cv::reduce(diff.reshape(1, diff.rows * diff.cols), differs, 1, cv::REDUCE_MAX);
  differs = differs.reshape(1, diff.rows) > 0;
  differs.setTo(0, near_people);
  EXPECT_LT(cv::countNonZero(differs), 0.01 * a.rgb.total());
  // Depth in whole millimetres, the calibration a user gets carries the lens.
  for (int y = 0; y < a.depth.rows; y += 7)
    for (int x = 0; x < a.depth.cols; x += 7) ASSERT_EQ(a.depth.at<std::uint16_t>(y, x) % 5, 0);
  EXPECT_NE(seq.camera().distortion.k1, 0.0);
  EXPECT_TRUE(seq.true_camera().distortion.is_zero());

  // Ground truth at the motion-capture rate, within a few millimetres of the true poses.
  const auto gt = seq.ground_truth();
  ASSERT_GT(gt.size(), 100u);
  EXPECT_NEAR(gt[1].timestamp - gt[0].timestamp, 0.01, 1e-6);  // stamps near 1.7e9 s
  EXPECT_GE(gt.back().timestamp, seq.timestamp(39));
  // Stamp s holds the pose at s + offset: interpolated there, it is the frame's pose to within the
  // motion capture's noise.
  double sum = 0.0, worst = 0.0;
  for (int i = 0; i < seq.size(); ++i) {
    const double s = seq.timestamp(i) - o.realism.gt_offset;
    std::size_t j = 0;
    while (j + 2 < gt.size() && gt[j + 1].timestamp <= s) ++j;
    const double f = (s - gt[j].timestamp) / (gt[j + 1].timestamp - gt[j].timestamp);
    const Eigen::Vector3d p = (1 - f) * gt[j].pose.translation() + f * gt[j + 1].pose.translation();
    const double e = (p - seq.pose(i).translation()).norm();
    sum += e;
    worst = std::max(worst, e);
  }
  EXPECT_LT(worst, 6 * o.realism.gt_position_sigma);
  EXPECT_GT(sum / seq.size(), 0.5 * o.realism.gt_position_sigma);
}

TEST(MotionStatistics, TumsOneSecondWindows) {
  // 0.2 m/s along x while turning at 10 deg/s about the optical axis, 10 s at 100 Hz.
  lrd::io::Trajectory t;
  for (int i = 0; i <= 1000; ++i) {
    const double s = i / 100.0;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(0.2 * s, 0.0, 1.0);
    pose.linear() = Eigen::AngleAxisd(10.0 * s * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    t.push_back({100.0 + s, pose});
  }
  const auto m = lrd::eval::motion_statistics(t);
  EXPECT_NEAR(m.duration, 10.0, 1e-9);
  EXPECT_NEAR(m.mean_speed, 0.2, 1e-9);
  EXPECT_NEAR(m.mean_angular_speed, 10.0, 1e-6);
  // TUM sums the windows that end within the trajectory: 901 of them, over the 100 Hz rate.
  EXPECT_NEAR(m.length, 901 * 0.2 / 100.0, 1e-9);
  // A back-and-forth at 1 Hz moves nothing over a whole second.
  for (auto& p : t) p.pose.translation().x() = 0.1 * std::sin(2.0 * M_PI * p.timestamp);
  EXPECT_LT(lrd::eval::motion_statistics(t).mean_speed, 1e-6);
  EXPECT_EQ(lrd::eval::motion_statistics({}).duration, 0.0);
}
