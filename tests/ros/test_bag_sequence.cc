// lrd_ros::BagSequence, the bag writer and the message conversions, on bags written here with
// rosbag_storage: frames, association, units, camera_info, /tf ground truth, and a one-line error
// naming the bag and the topic for every kind of bad bag.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "../unit/error_of.h"
#include "../unit/temp_dir.h"
#include "lrd/camera/pinhole_camera.h"
#include "lrd_ros/bag_sequence.h"
#include "lrd_ros/bag_writer.h"
#include "lrd_ros/image_messages.h"

namespace {

namespace fs = std::filesystem;
using lrd::test::error_of;
using lrd_ros::BagSequence;
using testing::HasSubstr;

constexpr const char* kRgb = "/camera/rgb/image_color";
constexpr const char* kDepth = "/camera/depth/image";

// A 4x3 colour image whose pixel (r, c) is (B, G, R) = (c, r, 10 * k).
cv::Mat colour(int k) {
  cv::Mat bgr(3, 4, CV_8UC3);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      bgr.at<cv::Vec3b>(r, c) = {static_cast<uchar>(c), static_cast<uchar>(r), static_cast<uchar>(10 * k)};
  return bgr;
}

cv::Mat depth_metres(float z) {
  return cv::Mat(3, 4, CV_32FC1, cv::Scalar(z));
}

class BagTest : public testing::Test {
 protected:
  lrd::test::TempDir dir_{"bag"};
  fs::path file_ = dir_.path() / "seq.bag";

  // Colour at t0 + k/30 and depth 5 ms later, k = 0..n-1.
  void write_frames(rosbag::Bag& bag, int n, double t0 = 100.0) {
    for (int k = 0; k < n; ++k) {
      const ros::Time tc = lrd_ros::to_stamp(t0 + k / 30.0), td = lrd_ros::to_stamp(t0 + k / 30.0 + 0.005);
      bag.write(kRgb, tc, lrd_ros::colour_message(colour(k), tc, "rgb"));
      bag.write(kDepth, td, lrd_ros::depth_message(depth_metres(1.0f + k), td, "depth"));
    }
  }
};

TEST_F(BagTest, ReadsFramesPairedByTheFolderReadersRule) {
  {
    rosbag::Bag bag(file_.string(), rosbag::bagmode::Write);
    write_frames(bag, 5);
    // A colour image without depth within 0.02 s is left out, as associate.py leaves it.
    const ros::Time lone = lrd_ros::to_stamp(200.0);
    bag.write(kRgb, lone, lrd_ros::colour_message(colour(9), lone, "rgb"));
  }
  const auto seq = BagSequence::open(file_);
  ASSERT_EQ(seq->size(), 5u);
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(seq->entry(k).timestamp, std::strtod(fmt::format("{:.6f}", 100.0 + k / 30.0).c_str(), nullptr));
    EXPECT_NEAR(seq->entry(k).depth_timestamp - seq->entry(k).timestamp, 0.005, 1e-6);
    const lrd::io::RgbdFrame f = seq->load_rgbd(k, 5000.0);
    EXPECT_EQ(f.index, k);
    ASSERT_EQ(f.rgb.type(), CV_8UC3);
    EXPECT_EQ(cv::norm(f.rgb, colour(static_cast<int>(k)), cv::NORM_INF), 0.0);  // rgb8 back to BGR
    ASSERT_EQ(f.depth.type(), CV_32FC1);
    EXPECT_EQ(f.depth.at<float>(1, 2), 1.0f + static_cast<float>(k));  // 32FC1 is metres as is
  }
  EXPECT_EQ(seq->entry(2).rgb_path.string(), fmt::format("rgb/{:.6f}.png", seq->entry(2).timestamp));
  EXPECT_FALSE(seq->folder());
  EXPECT_FALSE(seq->ground_truth());
  EXPECT_FALSE(seq->camera());  // no camera_info topic
}

TEST_F(BagTest, SortsMessagesThatArrivedOutOfStampOrder) {
  {
    rosbag::Bag bag(file_.string(), rosbag::bagmode::Write);
    for (int k : {2, 0, 1}) {
      const ros::Time t = lrd_ros::to_stamp(50.0 + k * 0.1);
      const ros::Time arrival = lrd_ros::to_stamp(60.0 + (2 - k));  // reversed arrival
      bag.write(kRgb, arrival, lrd_ros::colour_message(colour(k), t, "rgb"));
      bag.write(kDepth, arrival, lrd_ros::depth_message(depth_metres(1.0f), t, "depth"));
    }
  }
  const auto seq = BagSequence::open(file_);
  ASSERT_EQ(seq->size(), 3u);
  EXPECT_LT(seq->entry(0).timestamp, seq->entry(1).timestamp);
  EXPECT_LT(seq->entry(1).timestamp, seq->entry(2).timestamp);
  EXPECT_EQ(seq->load_rgbd(1, 1.0).rgb.at<cv::Vec3b>(0, 0)[2], 10);  // frame k = 1
}

TEST_F(BagTest, DepthUnitsAndInvalidValues) {
  sensor_msgs::Image mm;
  mm.width = 2;
  mm.height = 1;
  mm.encoding = "16UC1";
  mm.step = 4;
  const std::uint16_t raw[2] = {1234, 0};
  mm.data.resize(4);
  std::memcpy(mm.data.data(), raw, 4);
  const cv::Mat m = lrd_ros::depth_from_message(mm);
  EXPECT_FLOAT_EQ(m.at<float>(0, 0), 1.234f);  // millimetres (REP 118)
  EXPECT_EQ(m.at<float>(0, 1), 0.0f);

  cv::Mat z(1, 4, CV_32FC1);
  z.at<float>(0, 0) = std::numeric_limits<float>::quiet_NaN();
  z.at<float>(0, 1) = 1.5f;
  z.at<float>(0, 2) = std::numeric_limits<float>::infinity();
  z.at<float>(0, 3) = 2.5f;
  const cv::Mat out = lrd_ros::depth_from_message(lrd_ros::depth_message(z, ros::Time(1, 0), "d"));
  EXPECT_EQ(out.at<float>(0, 0), 0.0f);  // NaN: no return
  EXPECT_EQ(out.at<float>(0, 1), 1.5f);
  EXPECT_EQ(out.at<float>(0, 2), 0.0f);
  EXPECT_EQ(out.at<float>(0, 3), 2.5f);
  z.at<float>(0, 1) = -1.0f;
  EXPECT_THAT(
      error_of([&] { (void)lrd_ros::depth_from_message(lrd_ros::depth_message(z, ros::Time(1, 0), "d")); }),
      HasSubstr("1 pixels of negative depth (down to -1 m)"));
}

TEST(ImageMessages, MalformedMessagesAreErrorsNotCrashes) {
  sensor_msgs::Image good = lrd_ros::colour_message(colour(1), ros::Time(1, 0), "rgb");
  auto bad = good;
  bad.data.resize(bad.data.size() / 2);
  EXPECT_THAT(error_of([&] { (void)lrd_ros::colour_from_message(bad); }), HasSubstr("bytes of data"));
  bad = good;
  bad.width = 0;
  EXPECT_THAT(error_of([&] { (void)lrd_ros::colour_from_message(bad); }), HasSubstr("zero-size"));
  bad = good;
  bad.step = 3;
  EXPECT_THAT(error_of([&] { (void)lrd_ros::colour_from_message(bad); }), HasSubstr("step 3"));
  bad = good;
  bad.encoding = "yuv422";
  EXPECT_THAT(error_of([&] { (void)lrd_ros::colour_from_message(bad); }), HasSubstr("'yuv422'"));
  EXPECT_THAT(error_of([&] { (void)lrd_ros::depth_from_message(good); }), HasSubstr("not a depth encoding"));
  // A row stride that is no whole number of depth values (OpenCV would throw its own exception).
  auto odd = lrd_ros::depth_message(depth_metres(1.0f), ros::Time(1, 0), "d");
  odd.step += 2;
  odd.data.resize(static_cast<std::size_t>(odd.step) * odd.height);
  EXPECT_THAT(error_of([&] { (void)lrd_ros::depth_from_message(odd); }),
              HasSubstr("is not a whole number of 4-byte values"));
  sensor_msgs::CameraInfo info;
  info.width = 640;
  info.height = 480;
  EXPECT_THAT(error_of([&] { (void)lrd_ros::camera_from_message(info); }), HasSubstr("uncalibrated"));
}

TEST(ImageMessages, StampsRoundTripAsTheTextFilesParse) {
  for (const char* text : {"1305031102.175304", "1699999999.999853", "0.000001", "1341846313.553"}) {
    const double t = std::strtod(text, nullptr);
    const ros::Time stamp = lrd_ros::to_stamp(t);
    EXPECT_EQ(lrd_ros::to_seconds(stamp), t) << text;
  }
  EXPECT_EQ(lrd_ros::to_stamp(1305031102.175304).nsec, 175304000u);
  // Raw fields of a message, not normalised: 5 s + 1.5e9 ns is 6.5 s.
  ros::Time raw;
  raw.sec = 5;
  raw.nsec = 1500000000u;
  EXPECT_EQ(lrd_ros::to_seconds(raw), 6.5);
}

TEST_F(BagTest, CameraInfoAndGroundTruthThroughATfChain) {
  lrd::camera::PinholeCamera cam;
  cam.fx = 517.3;
  cam.fy = 516.5;
  cam.cx = 318.6;
  cam.cy = 255.3;
  cam.distortion = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
  {
    rosbag::Bag bag(file_.string(), rosbag::bagmode::Write);
    write_frames(bag, 3);
    bag.write("/camera/rgb/camera_info", ros::Time(100, 0),
              lrd_ros::camera_info_message(cam, ros::Time(100, 0), "rgb"));
    // /world -> /kinect moving along x at 1 m/s (100 Hz), /kinect -> /optical a static 10 cm up.
    for (int k = 0; k <= 20; ++k) {
      tf2_msgs::TFMessage m;
      geometry_msgs::TransformStamped t;
      t.header.stamp = lrd_ros::to_stamp(100.0 + k * 0.01);
      t.header.frame_id = "/world";
      t.child_frame_id = "/kinect";
      t.transform.translation.x = k * 0.01;
      t.transform.rotation.w = 1.0;
      m.transforms.push_back(t);
      bag.write("/tf", t.header.stamp, m);
    }
    tf2_msgs::TFMessage s;
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time(100, 0);
    t.header.frame_id = "kinect";
    t.child_frame_id = "optical";
    t.transform.translation.z = 0.1;
    t.transform.rotation.w = 1.0;
    s.transforms.push_back(t);
    bag.write("/tf_static", ros::Time(100, 0), s);
  }
  lrd_ros::BagTopics topics;
  topics.gt_parent = "/world";
  topics.gt_child = "/kinect";
  const auto seq = BagSequence::open(file_, topics);
  ASSERT_TRUE(seq->camera());
  EXPECT_EQ(seq->camera()->fx, 517.3);
  EXPECT_EQ(seq->camera()->cy, 255.3);
  EXPECT_EQ(seq->camera()->k3, 1.1633);
  EXPECT_EQ(seq->camera()->width, 640);
  ASSERT_TRUE(seq->ground_truth());
  ASSERT_EQ(seq->ground_truth()->size(), 21u);
  EXPECT_NEAR(seq->ground_truth()->at(7).pose.translation().x(), 0.07, 1e-12);
  // Through the static link of /tf_static: optical is 10 cm along kinect's z, sampled at the
  // motion capture's stamps.
  topics.gt_child = "/optical";
  const auto via_chain = BagSequence::open(file_, topics);
  ASSERT_TRUE(via_chain->ground_truth());
  ASSERT_EQ(via_chain->ground_truth()->size(), 21u);
  EXPECT_NEAR(via_chain->ground_truth()->at(7).pose.translation().x(), 0.07, 1e-12);
  EXPECT_NEAR(via_chain->ground_truth()->at(7).pose.translation().z(), 0.1, 1e-12);
  topics.gt_child = "/elsewhere";
  EXPECT_THAT(error_of([&] { (void)BagSequence::open(file_, topics); }),
              HasSubstr("--gt-from-tf /world:/elsewhere: no transform from /world to /elsewhere on /tf"));
}

TEST_F(BagTest, BadBagsAreOneLineErrorsNamingTheBagAndTopic) {
  // Missing file.
  std::string e = error_of([&] { (void)BagSequence::open(dir_.path() / "none.bag"); });
  EXPECT_THAT(e, HasSubstr("none.bag: bag file not found"));
  // Empty bag: no topics at all.
  { rosbag::Bag bag(file_.string(), rosbag::bagmode::Write); }
  e = error_of([&] { (void)BagSequence::open(file_); });
  EXPECT_THAT(e,
              HasSubstr(file_.string() + ": topic /camera/rgb/image_color not found; the bag has no topics"));
  // Missing depth topic.
  {
    rosbag::Bag bag(file_.string(), rosbag::bagmode::Write);
    const ros::Time t(5, 0);
    bag.write(kRgb, t, lrd_ros::colour_message(colour(0), t, "rgb"));
  }
  e = error_of([&] { (void)BagSequence::open(file_); });
  EXPECT_THAT(
      e, HasSubstr(
             "topic /camera/depth/image not found; the bag has /camera/rgb/image_color (sensor_msgs/Image)"));
  // Wrong message type on the colour topic.
  {
    rosbag::Bag bag(file_.string(), rosbag::bagmode::Write);
    const ros::Time t(5, 0);
    bag.write(kRgb, t, lrd_ros::camera_info_message(lrd::camera::PinholeCamera{}, t, "rgb"));
    bag.write(kDepth, t, lrd_ros::depth_message(depth_metres(1.0f), t, "d"));
  }
  e = error_of([&] { (void)BagSequence::open(file_); });
  EXPECT_THAT(
      e,
      HasSubstr("topic /camera/rgb/image_color carries sensor_msgs/CameraInfo, expected sensor_msgs/Image"));
  // Duplicate stamps.
  {
    rosbag::Bag bag(file_.string(), rosbag::bagmode::Write);
    write_frames(bag, 2);
    const ros::Time t = lrd_ros::to_stamp(100.0);
    bag.write(kRgb, t, lrd_ros::colour_message(colour(3), t, "rgb"));
  }
  e = error_of([&] { (void)BagSequence::open(file_); });
  EXPECT_THAT(e, HasSubstr("topic /camera/rgb/image_color: two messages stamped 100.000000000"));
  // Colour and depth never within 0.02 s.
  {
    rosbag::Bag bag(file_.string(), rosbag::bagmode::Write);
    const ros::Time a(10, 0), b(11, 0);
    bag.write(kRgb, a, lrd_ros::colour_message(colour(0), a, "rgb"));
    bag.write(kDepth, b, lrd_ros::depth_message(depth_metres(1.0f), b, "d"));
  }
  e = error_of([&] { (void)BagSequence::open(file_); });
  EXPECT_THAT(e, HasSubstr("none of the 1 messages on /camera/rgb/image_color has a depth image"));
  // Wrong depth encoding: found before any tracking.
  {
    rosbag::Bag bag(file_.string(), rosbag::bagmode::Write);
    const ros::Time a(10, 0);
    bag.write(kRgb, a, lrd_ros::colour_message(colour(0), a, "rgb"));
    bag.write(kDepth, a, lrd_ros::colour_message(colour(0), a, "d"));
  }
  e = error_of([&] { (void)BagSequence::open(file_); });
  EXPECT_THAT(e,
              HasSubstr("topic /camera/depth/image at 10.000000: encoding 'rgb8' is not a depth encoding"));
  // Truncated: a good bag cut in half.
  {
    rosbag::Bag bag(file_.string(), rosbag::bagmode::Write);
    write_frames(bag, 20);
  }
  const auto size = fs::file_size(file_);
  fs::resize_file(file_, size / 2);
  e = error_of([&] { (void)BagSequence::open(file_); });
  EXPECT_THAT(e, HasSubstr(file_.string() + ": cannot read the bag"));
  EXPECT_EQ(e.find('\n'), std::string::npos);
}

// rosbag_storage allocates what a bag states: lengths past the file and oversized chunks are refused
// by the structure check first (lrd/bag/ros1_bag_structure.h), with one line naming the bag.
TEST_F(BagTest, StatedLengthsThatCannotBeAreRefusedBeforeRosbagReads) {
  {
    rosbag::Bag bag(file_.string(), rosbag::bagmode::Write);
    write_frames(bag, 3);
  }
  std::string bytes;
  {
    std::ifstream in(file_, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  ASSERT_NO_THROW((void)BagSequence::open(file_));  // the bag as written passes
  const auto patched = [&](std::size_t at, std::uint32_t value) {
    std::string b = bytes;
    for (int i = 0; i < 4; ++i) b[at + i] = static_cast<char>((value >> (8 * i)) & 0xff);
    const fs::path out = dir_.path() / "patched.bag";
    std::ofstream(out, std::ios::binary | std::ios::trunc) << b;
    return error_of([&] { (void)BagSequence::open(out); });
  };
  // The bag header record's header length (right after the version line) at 2 GB.
  std::string e = patched(13, 0x7fffffffu);
  EXPECT_THAT(e,
              HasSubstr("patched.bag: cannot read the bag: record at byte 13 states a header of 2147483647"));
  EXPECT_EQ(e.find('\n'), std::string::npos);
  // A chunk's uncompressed size (its header field "size=") at 3.7 GB.
  const std::size_t size_field = bytes.find("size=");
  ASSERT_NE(size_field, std::string::npos);
  e = patched(size_field + 5, 0xf0000000u);
  EXPECT_THAT(e, HasSubstr("bytes uncompressed (at most"));
}

}  // namespace
