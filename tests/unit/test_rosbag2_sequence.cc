// ROS 2 bags as frame sources: a sequence written as MCAP or sqlite3 reads back frame for frame,
// bit for bit, with its camera and ground truth; every bad bag is one lrd::Error naming the file
// (and the topic); and the /tf ground truth follows chains as tf2 does.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <functional>
#include <opencv2/core.hpp>

#include "error_of.h"
#include "lrd/bag/tf_ground_truth.h"
#include "lrd/rosbag2/mcap_writer.h"
#include "lrd/rosbag2/messages.h"
#include "lrd/rosbag2/rosbag2_sequence.h"
#include "lrd/rosbag2/rosbag2_writer.h"
#include "temp_dir.h"

namespace lrd::rosbag2 {
namespace {

using test::error_of;
using test::TempDir;
namespace fs = std::filesystem;

// Frames of noise with depth in metres (some zeros), 30 Hz, depth 5 ms after colour.
class MemorySource final : public io::FrameSource {
 public:
  MemorySource(int frames, int width, int height) {
    cv::RNG rng(7);
    for (int i = 0; i < frames; ++i) {
      const double t = 1305031102.175304 + i / 30.0;
      const double td = std::stod(fmt::format("{:.6f}", t + 0.005));
      entries_.push_back({std::stod(fmt::format("{:.6f}", t)), fmt::format("rgb/{}.png", i), td,
                          fmt::format("depth/{}.png", i)});
      cv::Mat rgb(height, width, CV_8UC3), depth(height, width, CV_32FC1);
      rng.fill(rgb, cv::RNG::UNIFORM, 0, 256);
      rng.fill(depth, cv::RNG::UNIFORM, 0.0, 4.0);
      depth.at<float>(0, 0) = 0.0f;
      frames_.push_back({static_cast<std::size_t>(i), entries_.back().timestamp, rgb, depth});
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.translate(Eigen::Vector3d(0.01 * i, -0.02 * i, 1.0));
      pose.rotate(Eigen::AngleAxisd(0.03 * i, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()));
      gt_.push_back({entries_.back().timestamp, pose});
    }
  }
  std::size_t size() const override { return entries_.size(); }
  const io::FrameEntry& entry(std::size_t i) const override { return entries_.at(i); }
  io::RgbdFrame load_rgbd(std::size_t i, double) const override { return frames_.at(i); }
  std::string describe(std::size_t i) const override { return entries_.at(i).rgb_path.string(); }
  fs::path path() const override { return "memory"; }
  std::optional<fs::path> folder() const override { return std::nullopt; }
  std::optional<io::Trajectory> ground_truth() const override { return gt_; }
  std::string ground_truth_origin() const override { return "memory"; }

 private:
  std::vector<io::FrameEntry> entries_;
  std::vector<io::RgbdFrame> frames_;
  io::Trajectory gt_;
};

camera::PinholeCamera camera_of(int width, int height) {
  camera::PinholeCamera c;
  c.width = width;
  c.height = height;
  c.fx = 50.5;
  c.fy = 51.25;
  c.cx = width / 2.0;
  c.cy = height / 2.0;
  c.distortion.k1 = 0.01;
  return c;
}

bool same_bits(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() &&
         std::equal(a.datastart, a.dataend, b.datastart);  // continuous: both freshly allocated
}

bag::BagTopics with_ground_truth() {
  bag::BagTopics t;
  t.gt_parent = "/world";
  t.gt_child = "/kinect";
  return t;
}

void expect_sequence_reads_back(const std::string& extension) {
  TempDir dir("rosbag2");
  const MemorySource source(12, 32, 24);
  const fs::path file = dir.path() / ("seq" + extension);
  write_rosbag2(source, camera_of(32, 24), file);
  // A .db3 is a rosbag2 folder: readable as the file and as the folder.
  for (const fs::path& path :
       extension == ".db3" ? std::vector<fs::path>{file, dir.path()} : std::vector{file}) {
    const auto seq = Rosbag2Sequence::open(path, with_ground_truth());
    ASSERT_EQ(seq->size(), source.size()) << path;
    for (std::size_t i = 0; i < source.size(); ++i) {
      EXPECT_EQ(seq->entry(i).timestamp, source.entry(i).timestamp);
      EXPECT_EQ(seq->entry(i).depth_timestamp, source.entry(i).depth_timestamp);
      EXPECT_EQ(seq->entry(i).rgb_path,
                fs::path("rgb") / fmt::format("{:.6f}.png", source.entry(i).timestamp));
      const io::RgbdFrame f = seq->load_rgbd(i, 5000.0), g = source.load_rgbd(i, 5000.0);
      EXPECT_TRUE(same_bits(f.rgb, g.rgb)) << i;
      EXPECT_TRUE(same_bits(f.depth, g.depth)) << i;
    }
    const auto c = seq->camera();
    ASSERT_TRUE(c);
    EXPECT_EQ(c->width, 32);
    EXPECT_EQ(c->fy, 51.25);
    EXPECT_EQ(c->k1, 0.01);
    EXPECT_NE(c->origin.find("camera_info /camera/rgb/camera_info in " + file.string()), std::string::npos);
    const auto gt = seq->ground_truth();
    ASSERT_TRUE(gt);
    ASSERT_EQ(gt->size(), source.size());
    for (std::size_t i = 0; i < gt->size(); ++i) {
      EXPECT_EQ((*gt)[i].timestamp, (*source.ground_truth())[i].timestamp);
      EXPECT_TRUE((*gt)[i].pose.isApprox((*source.ground_truth())[i].pose, 1e-12));
    }
  }
  if (extension == ".db3") {
    const std::string metadata = TempDir::read(dir.path() / "metadata.yaml");
    EXPECT_NE(metadata.find("storage_identifier: sqlite3"), std::string::npos);
    EXPECT_NE(metadata.find("message_count: 60\n"), std::string::npos) << metadata;  // 4 x 12 + 12 /tf
    EXPECT_NE(metadata.find("    - seq.db3\n"), std::string::npos);
  }
}

TEST(Rosbag2, AnMcapSequenceReadsBackBitForBit) {
  expect_sequence_reads_back(".mcap");
}
TEST(Rosbag2, ASqlite3SequenceReadsBackBitForBit) {
  expect_sequence_reads_back(".db3");
}

// A bag with the given messages on the colour and depth topics (and a camera_info of 32x24).
void write_bag_by_hand(const fs::path& file, const std::string& rgb_type,
                       const std::function<std::vector<std::uint8_t>(int)>& rgb_message) {
  McapWriter w(file);
  const std::uint16_t s_rgb = w.add_schema(rgb_type, "ros2msg", "uint8 x\n");
  const std::uint16_t s_img = w.add_schema(msg::kImageType, "ros2msg", msg::definition(msg::kImageType));
  const std::uint16_t s_info =
      w.add_schema(msg::kCameraInfoType, "ros2msg", msg::definition(msg::kCameraInfoType));
  const std::uint16_t rgb = w.add_channel(s_rgb, "/camera/rgb/image_color", "cdr");
  const std::uint16_t depth = w.add_channel(s_img, "/camera/depth/image", "cdr");
  const std::uint16_t info = w.add_channel(s_info, "/camera/rgb/camera_info", "cdr");
  msg::CameraInfo c;
  c.width = 32;
  c.height = 24;
  c.k = {50, 0, 16, 0, 50, 12, 0, 0, 1};
  w.write(info, 1000000000, msg::encode(c));
  for (int i = 0; i < 3; ++i) {
    msg::Image d;
    d.header.stamp = {100 + i, 0};
    d.width = 32;
    d.height = 24;
    d.encoding = "16UC1";
    d.step = 64;
    d.data.assign(64 * 24, 1);
    w.write(rgb, 1000000000 + i, rgb_message(i));
    w.write(depth, 1000000000 + i, msg::encode(d));
  }
  w.close();
}

msg::Image mono_image(int i, std::uint32_t width, std::uint32_t height) {
  msg::Image m;
  m.header.stamp = {100 + i, 0};
  m.width = width;
  m.height = height;
  m.encoding = "mono8";
  m.step = width;
  m.data.assign(static_cast<std::size_t>(width) * height, 9);
  return m;
}

void expect_one_line(const std::string& e, const fs::path& file, const std::string& part) {
  EXPECT_EQ(e.rfind(file.string() + ": ", 0), 0u) << e;
  EXPECT_NE(e.find(part), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

TEST(Rosbag2BadInput, AWrongTypeOnTheImageTopicNamesTheTopicAndBothTypes) {
  TempDir dir("rosbag2");
  const fs::path file = dir.path() / "x.mcap";
  write_bag_by_hand(file, msg::kCameraInfoType, [](int i) { return msg::encode(mono_image(i, 32, 24)); });
  expect_one_line(
      error_of([&] { (void)Rosbag2Sequence::open(file); }), file,
      "topic /camera/rgb/image_color carries sensor_msgs/msg/CameraInfo, expected sensor_msgs/msg/Image");
}

TEST(Rosbag2BadInput, AMessageShorterThanItsFieldsNamesTheTopicAndField) {
  TempDir dir("rosbag2");
  const fs::path file = dir.path() / "x.mcap";
  write_bag_by_hand(file, msg::kImageType, [](int i) {
    std::vector<std::uint8_t> bytes = msg::encode(mono_image(i, 32, 24));
    if (i == 0) bytes.resize(bytes.size() - 100);  // its pixels cut short
    return bytes;
  });
  expect_one_line(error_of([&] { (void)Rosbag2Sequence::open(file); }), file,
                  "topic /camera/rgb/image_color: the message recorded at 1.000000000 s cannot be read: CDR "
                  "message of");
  write_bag_by_hand(file, msg::kImageType, [](int i) {
    std::vector<std::uint8_t> bytes = msg::encode(mono_image(i, 32, 24));
    bytes.resize(i == 2 ? 9 : bytes.size());  // its header cut short
    return bytes;
  });
  expect_one_line(error_of([&] { (void)Rosbag2Sequence::open(file); }), file,
                  "ends inside 'header.stamp.nanosec'");
}

TEST(Rosbag2BadInput, AnImageOfAnotherSizeThanCameraInfoIsNamed) {
  TempDir dir("rosbag2");
  const fs::path file = dir.path() / "x.mcap";
  write_bag_by_hand(file, msg::kImageType, [](int i) { return msg::encode(mono_image(i, 32, 24)); });
  EXPECT_EQ(Rosbag2Sequence::open(file)->size(), 3u);  // the bag itself is good
  write_bag_by_hand(file, msg::kImageType, [](int i) { return msg::encode(mono_image(i, 40, 30)); });
  expect_one_line(
      error_of([&] { (void)Rosbag2Sequence::open(file); }), file,
      "/camera/rgb/image_color at 100.000000 is 40x30 but its depth on /camera/depth/image is 32x24");
  // Colour and depth of one size, camera_info of another.
  const MemorySource source(3, 32, 24);
  write_rosbag2(source, camera_of(64, 48), file);
  expect_one_line(error_of([&] { (void)Rosbag2Sequence::open(file); }), file,
                  "is 32x24 but /camera/rgb/camera_info says 64x48");
}

TEST(Rosbag2BadInput, MissingTopicsPathsAndGroundTruthFramesAreNamed) {
  TempDir dir("rosbag2");
  const fs::path file = dir.path() / "x.db3";
  write_rosbag2(MemorySource(3, 32, 24), camera_of(32, 24), file);
  bag::BagTopics t;
  t.rgb = "/nope";
  expect_one_line(
      error_of([&] { (void)Rosbag2Sequence::open(file, t); }), file,
      "topic /nope not found; the bag has /camera/depth/camera_info (sensor_msgs/msg/CameraInfo)");
  t = with_ground_truth();
  t.gt_child = "/nowhere";
  expect_one_line(error_of([&] { (void)Rosbag2Sequence::open(file, t); }), file,
                  "no transform from /world to /nowhere on /tf (frames: kinect world)");
  const fs::path missing = dir.path() / "missing.mcap";
  expect_one_line(error_of([&] { (void)Rosbag2Sequence::open(missing); }), missing, "bag not found");
  const fs::path folder = dir.path() / "empty";
  fs::create_directories(folder);
  expect_one_line(error_of([&] { (void)Rosbag2Sequence::open(folder); }), folder, "without metadata.yaml");
  const fs::path cut = dir.write("cut.db3", TempDir::read(file).substr(0, 5000));
  expect_one_line(error_of([&] { (void)Rosbag2Sequence::open(cut); }), cut, "truncated SQLite database");
}

TEST(Rosbag2TfGroundTruth, ChainsInterpolateAndFollowStaticLinks) {
  bag::TfGroundTruth tf;
  Eigen::Isometry3d a = Eigen::Isometry3d::Identity(), b = Eigen::Isometry3d::Identity();
  b.translation() = Eigen::Vector3d(2.0, 0.0, 0.0);
  b.rotate(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
  Eigen::Isometry3d optical = Eigen::Isometry3d::Identity();
  optical.translation() = Eigen::Vector3d(0.0, 0.1, 0.0);
  tf.add("/world", "/base", {10, 0}, a, false);
  tf.add("/world", "/base", {11, 0}, b, false);
  tf.add("/base", "/camera", {0, 0}, optical, true);
  bag::BagTopics t;
  t.gt_parent = "/world";
  t.gt_child = "/camera";
  const io::Trajectory gt = tf.trajectory("bag", t);
  ASSERT_EQ(gt.size(), 2u);
  EXPECT_EQ(gt[0].timestamp, 10.0);
  EXPECT_TRUE(gt[1].pose.isApprox(b * optical, 1e-12));
  // Halfway between two /tf samples of the link above: half the translation and half the angle.
  tf.add("/base", "/marker", {10, 500000000}, Eigen::Isometry3d::Identity(), false);
  t.gt_child = "/marker";
  const io::Trajectory mid = tf.trajectory("bag", t);
  ASSERT_EQ(mid.size(), 1u);
  EXPECT_EQ(mid[0].timestamp, 10.5);
  EXPECT_NEAR(mid[0].pose.translation().x(), 1.0, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(mid[0].pose.linear()).angle(), 0.25, 1e-12);
  // The other way round: the parent's pose in its child.
  t.gt_parent = "/camera";
  t.gt_child = "/world";
  EXPECT_NE(error_of([&] { (void)tf.trajectory("bag", t); }).find("no transform from /camera to /world"),
            std::string::npos);
}

}  // namespace
}  // namespace lrd::rosbag2
