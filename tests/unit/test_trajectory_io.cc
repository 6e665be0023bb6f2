// lrd::io trajectory files: TUM read/write round trip, TUM parsing rules, errors, KITTI format.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "lrd/io/trajectory.h"
#include "lrd/util/error.h"
#include "temp_dir.h"

namespace {

namespace fs = std::filesystem;
using lrd::io::StampedPose;
using lrd::io::Trajectory;

// One scratch folder for the file's tests, removed at exit.
const lrd::test::TempDir& scratch() {
  static const lrd::test::TempDir dir("traj");
  return dir;
}
fs::path temp_file(const std::string& name) {
  return scratch().path() / name;
}
fs::path write_text(const std::string& name, const std::string& text) {
  return scratch().write(name, text);
}
std::string read_text(const fs::path& file) {
  return lrd::test::TempDir::read(file);
}

StampedPose make_pose(double t, const Eigen::Quaterniond& q, const Eigen::Vector3d& p) {
  StampedPose pose;
  pose.timestamp = t;
  pose.pose.linear() = q.normalized().toRotationMatrix();
  pose.pose.translation() = p;
  return pose;
}

// The message of the lrd::Error that `f` throws, or "" when it throws none.
template <typename F>
std::string error_message(F&& f) {
  try {
    f();
  } catch (const lrd::Error& e) {
    return e.what();
  }
  return "";
}

TEST(TrajectoryIo, TumRoundTripTo1e9) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  Trajectory poses;
  for (int k = 0; k < 200; ++k) {
    const Eigen::Quaterniond q(
        Eigen::AngleAxisd(u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()));
    // TUM timestamps have 6 decimals; the double nearest such a decimal survives %.6f exactly.
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "%.6f", 1305031102.175304 + 0.033333 * k);
    poses.push_back(make_pose(std::strtod(stamp, nullptr), q, Eigen::Vector3d(u(rng), u(rng), u(rng))));
  }
  const fs::path file = temp_file("roundtrip.txt");
  lrd::io::write_trajectory_tum(file, poses);
  const Trajectory back = lrd::io::read_trajectory_tum(file);
  ASSERT_EQ(back.size(), poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    EXPECT_EQ(back[k].timestamp, poses[k].timestamp);
    EXPECT_LE((back[k].pose.translation() - poses[k].pose.translation()).cwiseAbs().maxCoeff(), 1e-9);
    // Each printed quaternion component is within 5e-10, so the angle between the rotations is < 2e-9.
    const Eigen::Quaterniond a(back[k].pose.linear()), b(poses[k].pose.linear());
    EXPECT_LE(a.angularDistance(b), 2e-9);
  }

  // Quaternions exact in 9 decimals come back to 1e-9 in every matrix entry.
  const Trajectory exact = {make_pose(1.0, Eigen::Quaterniond(0.48, 0.36, 0.48, 0.64), {0.5, -1.25, 2.0}),
                            make_pose(2.0, Eigen::Quaterniond(0.8, 0.0, 0.6, 0.0), {1e-9, 0.0, -3.0})};
  lrd::io::write_trajectory_tum(file, exact);
  const Trajectory exact_back = lrd::io::read_trajectory_tum(file);
  ASSERT_EQ(exact_back.size(), 2u);
  for (std::size_t k = 0; k < exact.size(); ++k) {
    EXPECT_LE((exact_back[k].pose.matrix() - exact[k].pose.matrix()).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(TrajectoryIo, TumWriterFormat) {
  const fs::path file = temp_file("format.txt");
  lrd::io::write_trajectory_tum(file,
                                {make_pose(1.5, Eigen::Quaterniond(0.8, 0.0, 0.6, 0.0), {1.0, -2.0, 0.25})});
  EXPECT_EQ(
      read_text(file),
      "# timestamp tx ty tz qx qy qz qw\n"
      "1.500000 1.000000000 -2.000000000 0.250000000 0.000000000 0.600000000 0.000000000 0.800000000\n");
}

TEST(TrajectoryIo, TumParsingFollowsEvaluateRpe) {
  const fs::path file = write_text("parsing.txt",
                                   "# comment\n"
                                   "\n"
                                   "3.0,1,2,3,0,0,0,2\r\n"  // commas, CRLF, non-unit quaternion
                                   "1.0\t0.5\t0\t0\t0\t0\t0.7071068\t0.7071068\n"  // tabs
                                   "   \n"                                         // blank
                                   "2.0 nan 0 0 0 0 0 1\n"                         // NaN: skipped
                                   "2.5 1 1 1 0 0 0 0\n"              // all-zero quaternion: skipped
                                   "4.0 +1 -2e-1 .5 0 0 -0.0 -3\n");  // '+', exponent, leading '.'
  const Trajectory t = lrd::io::read_trajectory_tum(file);
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0].timestamp, 1.0);  // sorted by timestamp
  EXPECT_EQ(t[1].timestamp, 3.0);
  EXPECT_EQ(t[2].timestamp, 4.0);
  EXPECT_NEAR((t[0].pose.linear() - Eigen::Matrix3d(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())))
                  .cwiseAbs()
                  .maxCoeff(),
              0.0, 1e-7);
  EXPECT_EQ(t[1].pose.translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_LE((t[1].pose.linear() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(),
            1e-15);  // (0,0,0,2) -> identity
  EXPECT_EQ(t[2].pose.translation(), Eigen::Vector3d(1.0, -0.2, 0.5));
  EXPECT_LE((t[2].pose.linear() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-15);  // qw = -3
}

TEST(TrajectoryIo, MissingFileNamesFile) {
  const fs::path file = temp_file("does_not_exist.txt");
  const std::string msg = error_message([&] { (void)lrd::io::read_trajectory_tum(file); });
  EXPECT_EQ(msg, file.string() + ": no such trajectory file");
}

TEST(TrajectoryIo, WrongFieldCountNamesFileAndLine) {
  const fs::path file = write_text("fields.txt", "# header\n1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n");
  const std::string msg = error_message([&] { (void)lrd::io::read_trajectory_tum(file); });
  EXPECT_EQ(msg, file.string() + ":3: expected 8 fields 'timestamp tx ty tz qx qy qz qw', found 7");
}

TEST(TrajectoryIo, NonNumericFieldNamesFileAndLine) {
  const fs::path file = write_text("nonnumeric.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0x 0 0 0 0 1\n");
  const std::string msg = error_message([&] { (void)lrd::io::read_trajectory_tum(file); });
  EXPECT_EQ(msg, file.string() + ":2: field 3 '0x' is not a number");
  const fs::path inf = write_text("inf.txt", "1.0 inf 0 0 0 0 0 1\n");
  EXPECT_EQ(error_message([&] { (void)lrd::io::read_trajectory_tum(inf); }),
            inf.string() + ":1: field 2 is infinite");
}

TEST(TrajectoryIo, DuplicateTimestampNamesFileAndLine) {
  const fs::path file =
      write_text("duplicate.txt", "# header\n2.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n2.000000 1 0 0 0 0 0 1\n");
  const std::string msg = error_message([&] { (void)lrd::io::read_trajectory_tum(file); });
  EXPECT_EQ(msg, file.string() + ":4: duplicate timestamp 2.000000 (first seen on line 2)");
}

TEST(TrajectoryIo, KittiWriterFormat) {
  StampedPose p;
  p.timestamp = 7.0;
  p.pose.linear() << 0, -1, 0, 1, 0, 0, 0, 0, 1;  // 90 degrees about z
  p.pose.translation() = Eigen::Vector3d(1.5, -2.0, 0.001);
  const fs::path file = temp_file("kitti.txt");
  lrd::io::write_trajectory_kitti(file, {StampedPose{}, p});
  EXPECT_EQ(read_text(file),
            "1.000000000e+00 0.000000000e+00 0.000000000e+00 0.000000000e+00 "
            "0.000000000e+00 1.000000000e+00 0.000000000e+00 0.000000000e+00 "
            "0.000000000e+00 0.000000000e+00 1.000000000e+00 0.000000000e+00\n"
            "0.000000000e+00 -1.000000000e+00 0.000000000e+00 1.500000000e+00 "
            "1.000000000e+00 0.000000000e+00 0.000000000e+00 -2.000000000e+00 "
            "0.000000000e+00 0.000000000e+00 1.000000000e+00 1.000000000e-03\n");
}

TEST(TrajectoryIo, UnwritableFileNamesFile) {
  const fs::path file = temp_file("no_such_dir") / "x.txt";
  EXPECT_EQ(error_message([&] { lrd::io::write_trajectory_tum(file, {}); }),
            file.string() + ": cannot open for writing (No such file or directory)");
}

// A 100 Hz motion-capture trajectory on its own clock, read at an image's stamp between two samples.
TEST(TrajectoryIo, PoseAtInterpolatesBetweenTheSamplesAroundAStamp) {
  auto pose = [](double t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.5 * t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(2.0 * t, -t, 0.3);
    return T;
  };
  Trajectory gt;
  for (int j = 0; j <= 100; ++j) gt.push_back({0.004 + 0.01 * j, pose(0.004 + 0.01 * j)});

  const auto between = lrd::io::pose_at(gt, 0.5013, 0.02);
  ASSERT_TRUE(between.has_value());
  EXPECT_LT((between->translation() - pose(0.5013).translation()).norm(), 1e-12);
  EXPECT_LT(Eigen::AngleAxisd(between->linear().transpose() * pose(0.5013).linear()).angle(), 1e-12);
  const auto exact = lrd::io::pose_at(gt, gt[7].timestamp, 0.02);
  ASSERT_TRUE(exact.has_value());
  EXPECT_TRUE(exact->isApprox(gt[7].pose, 0.0));

  EXPECT_FALSE(lrd::io::pose_at(gt, 0.001, 0.02).has_value());  // before the first sample
  EXPECT_FALSE(lrd::io::pose_at(gt, 1.2, 0.02).has_value());    // after the last
  gt.erase(gt.begin() + 40, gt.begin() + 50);                   // a gap of 0.11 s
  EXPECT_FALSE(lrd::io::pose_at(gt, 0.44, 0.02).has_value());
}

}  // namespace
