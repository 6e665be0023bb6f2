// lrd::io::TumSequence, load_rgbd_frame and FramePrefetcher on a tiny generated sequence.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <string>
#include <vector>

#include "lrd/io/frame_prefetcher.h"
#include "lrd/io/tum_sequence.h"
#include "lrd/util/error.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using lrd::io::FramePrefetcher;
using lrd::io::TumSequence;

namespace {

// rgb/depth stamps a few ms apart, as in TUM. Unmatched: rgb 1.200 (no depth near), depth
// 0.950 (no rgb near), and rgb 1.300, which loses depth 1.306 to rgb 1.310 (0.004 < 0.006):
// associate.py is greedy on the smallest difference, not nearest-per-rgb.
const std::vector<std::string> kRgb = {"1.000", "1.033", "1.066", "1.100", "1.200", "1.300", "1.310"};
const std::vector<std::string> kDepth = {"0.950", "1.004", "1.030", "1.070", "1.098", "1.306"};
// Hand-computed association (rgb, depth).
const std::vector<std::pair<double, double>> kExpected = {
    {1.000, 1.004}, {1.033, 1.030}, {1.066, 1.070}, {1.100, 1.098}, {1.310, 1.306}};
constexpr int kW = 64, kH = 48;
constexpr int kHeaderLines = 3;  // comment lines before the first entry

class TumSequenceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(dir_ / "rgb");
    fs::create_directories(dir_ / "depth");
    write_list("rgb.txt", "rgb", kRgb);
    write_list("depth.txt", "depth", kDepth);
    for (std::size_t i = 0; i < kExpected.size(); ++i) {
      cv::Mat rgb(kH, kW, CV_8UC3, cv::Scalar(10.0 * i, 20, 30));
      rgb.at<cv::Vec3b>(0, 0) = {1, 2, 3};  // B, G, R
      ASSERT_TRUE(cv::imwrite(rgb_file(i).string(), rgb));
      cv::Mat depth(kH, kW, CV_16UC1, cv::Scalar(1000 * (i + 1)));
      depth.at<std::uint16_t>(0, 0) = 5000;
      depth.at<std::uint16_t>(0, 1) = 0;
      depth.at<std::uint16_t>(0, 2) = 1234;
      ASSERT_TRUE(cv::imwrite(depth_file(i).string(), depth));
    }
  }

  static std::string stamp(double t) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3f", t);
    return buf;
  }
  fs::path rgb_file(std::size_t i) const { return dir_ / "rgb" / (stamp(kExpected[i].first) + ".png"); }
  fs::path depth_file(std::size_t i) const { return dir_ / "depth" / (stamp(kExpected[i].second) + ".png"); }

  void write_list(const std::string& name, const std::string& folder,
                  const std::vector<std::string>& stamps) {
    std::ofstream out(dir_ / name);
    out << "# " << folder << " images\n# file: 'tiny.bag'\n# timestamp filename\n";
    for (const auto& s : stamps) out << s << " " << folder << "/" << s << ".png\n";
  }
  void write_text(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
  }

  // The message of the lrd::Error that f throws.
  template <class F>
  static std::string error_of(F f) {
    try {
      f();
    } catch (const lrd::Error& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
      return msg;
    }
    ADD_FAILURE() << "expected lrd::Error";
    return {};
  }
  std::string open_error() const {
    return error_of([&] { (void)TumSequence::open(dir_); });
  }

  lrd::test::TempDir tmp_{"tum"};
  const fs::path dir_ = tmp_.path();
};

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace

TEST_F(TumSequenceTest, AssociatesLikeAssociatePy) {
  const auto seq = TumSequence::open(dir_);
  ASSERT_EQ(seq.size(), kExpected.size());
  EXPECT_EQ(seq.dir(), dir_);
  for (std::size_t i = 0; i < kExpected.size(); ++i) {
    EXPECT_DOUBLE_EQ(seq.entry(i).timestamp, kExpected[i].first) << i;
    EXPECT_DOUBLE_EQ(seq.entry(i).depth_timestamp, kExpected[i].second) << i;
    EXPECT_EQ(seq.entry(i).rgb_path, rgb_file(i));
    EXPECT_EQ(seq.entry(i).depth_path, depth_file(i));
  }
  EXPECT_FALSE(seq.groundtruth_path().has_value());
  // A tighter max_dt drops the pairs 4 ms or more apart: only (1.033, 1.030) and (1.100, 1.098) stay.
  const auto tight = TumSequence::open(dir_, 0.0035);
  ASSERT_EQ(tight.size(), 2u);
  EXPECT_DOUBLE_EQ(tight.entry(0).timestamp, 1.033);
  EXPECT_DOUBLE_EQ(tight.entry(1).timestamp, 1.100);
}

TEST_F(TumSequenceTest, GroundtruthPathExposed) {
  write_text("groundtruth.txt", "# timestamp tx ty tz qx qy qz qw\n1.0 0 0 0 0 0 0 1\n");
  const auto seq = TumSequence::open(dir_);
  ASSERT_TRUE(seq.groundtruth_path().has_value());
  EXPECT_EQ(*seq.groundtruth_path(), dir_ / "groundtruth.txt");
}

TEST_F(TumSequenceTest, AssociationsFileUsedInstead) {
  // Pairs as given, even ones associate.py would not make; rgb.txt/depth.txt not needed.
  fs::remove(dir_ / "rgb.txt");
  fs::remove(dir_ / "depth.txt");
  write_text("associations.txt",
             "# t_rgb rgb t_depth depth\n1.000 rgb/1.000.png 1.030 depth/1.030.png\n"
             "1.100 rgb/1.100.png 1.098 depth/1.098.png\n");
  const auto seq = TumSequence::open(dir_);
  ASSERT_EQ(seq.size(), 2u);
  EXPECT_DOUBLE_EQ(seq.entry(0).timestamp, 1.000);
  EXPECT_DOUBLE_EQ(seq.entry(0).depth_timestamp, 1.030);
  EXPECT_EQ(seq.entry(0).depth_path, dir_ / "depth" / "1.030.png");
  EXPECT_DOUBLE_EQ(seq.entry(1).timestamp, 1.100);

  write_text("associations.txt", "1.000 rgb/1.000.png 1.030\n");
  const std::string msg = open_error();
  EXPECT_TRUE(contains(msg, "associations.txt:1: malformed line")) << msg;
}

TEST_F(TumSequenceTest, LoadsRgbAndMetricDepth) {
  const auto seq = TumSequence::open(dir_);
  const auto f = seq.load_rgbd(2, 5000.0);
  EXPECT_EQ(f.index, 2u);
  EXPECT_DOUBLE_EQ(f.timestamp, 1.066);
  ASSERT_EQ(f.rgb.type(), CV_8UC3);
  ASSERT_EQ(f.depth.type(), CV_32FC1);
  EXPECT_EQ(f.rgb.size(), cv::Size(kW, kH));
  EXPECT_EQ(f.rgb.at<cv::Vec3b>(0, 0), cv::Vec3b(1, 2, 3));  // BGR as written
  EXPECT_EQ(f.rgb.at<cv::Vec3b>(5, 5), cv::Vec3b(20, 20, 30));
  EXPECT_EQ(f.depth.at<float>(0, 0), 1.0f);  // 5000 / 5000, exactly
  EXPECT_EQ(f.depth.at<float>(0, 1), 0.0f);  // invalid stays 0
  EXPECT_EQ(f.depth.at<float>(0, 2), static_cast<float>(1234 / 5000.0));
  EXPECT_EQ(f.depth.at<float>(10, 10), 0.6f);  // 3000 / 5000
  EXPECT_EQ(seq.load_rgbd(0, 1000.0).depth.at<float>(0, 0), 5.0f);
}

TEST_F(TumSequenceTest, MissingFolderAndLists) {
  std::string msg = error_of([&] { (void)TumSequence::open(dir_ / "nope"); });
  EXPECT_TRUE(contains(msg, (dir_ / "nope").string() + ": sequence folder not found")) << msg;

  fs::remove(dir_ / "depth.txt");
  msg = open_error();
  EXPECT_TRUE(contains(msg, (dir_ / "depth.txt").string() + ": file not found")) << msg;
  fs::remove(dir_ / "rgb.txt");
  msg = open_error();
  EXPECT_TRUE(contains(msg, (dir_ / "rgb.txt").string() + ": file not found")) << msg;
}

TEST_F(TumSequenceTest, MalformedLineNamesFileAndLine) {
  write_text("rgb.txt", "# c\n1.000 rgb/1.000.png\n1.033\n");
  std::string msg = open_error();
  EXPECT_TRUE(contains(msg, "rgb.txt:3: malformed line")) << msg;
  write_text("depth.txt", "1.004 depth/1.004.png\n1.03x depth/1.030.png\n");
  write_list("rgb.txt", "rgb", kRgb);
  msg = open_error();
  EXPECT_TRUE(contains(msg, "depth.txt:2: malformed line: '1.03x' is not a timestamp")) << msg;
}

TEST_F(TumSequenceTest, UnsortedAndDuplicateTimestamps) {
  write_list("rgb.txt", "rgb", {"1.000", "1.066", "1.033", "1.100"});
  std::string msg = open_error();
  EXPECT_TRUE(contains(msg, "rgb.txt:" + std::to_string(kHeaderLines + 3) + ": timestamps not sorted"))
      << msg;
  write_list("rgb.txt", "rgb", kRgb);
  write_list("depth.txt", "depth", {"1.004", "1.030", "1.030", "1.070"});
  msg = open_error();
  EXPECT_TRUE(contains(msg, "depth.txt:" + std::to_string(kHeaderLines + 3) + ": duplicate timestamp 1.030"))
      << msg;
}

TEST_F(TumSequenceTest, EmptySequence) {
  write_text("rgb.txt", "# only comments\n\n");
  std::string msg = open_error();
  EXPECT_TRUE(contains(msg, "rgb.txt: no frames listed")) << msg;
  write_list("rgb.txt", "rgb", {"5.000", "6.000"});  // nothing within 20 ms of a depth stamp
  msg = open_error();
  EXPECT_TRUE(contains(msg, "rgb.txt: empty sequence")) << msg;
  EXPECT_TRUE(contains(msg, "0.02 s")) << msg;
}

TEST_F(TumSequenceTest, MissingImageFile) {
  fs::remove(rgb_file(1));
  const std::string msg = open_error();
  EXPECT_TRUE(contains(msg, "rgb.txt:" + std::to_string(kHeaderLines + 2) + ": image file not found")) << msg;
  EXPECT_TRUE(contains(msg, rgb_file(1).string())) << msg;
}

TEST_F(TumSequenceTest, BadImagesAtLoad) {
  const auto seq = TumSequence::open(dir_);
  // Removed after open.
  fs::remove(depth_file(0));
  std::string msg = error_of([&] { (void)seq.load_rgbd(0, 5000.0); });
  EXPECT_TRUE(contains(msg, depth_file(0).string() + ": image file not found")) << msg;
  // Garbage bytes.
  std::ofstream(depth_file(1), std::ios::binary) << "\x89PNG this is not really a png";
  msg = error_of([&] { (void)seq.load_rgbd(1, 5000.0); });
  EXPECT_TRUE(contains(msg, depth_file(1).string() + ": cannot decode image")) << msg;
  std::ofstream(rgb_file(1), std::ios::binary) << "garbage";
  msg = error_of([&] { (void)seq.load_rgbd(1, 5000.0); });
  EXPECT_TRUE(contains(msg, rgb_file(1).string() + ": cannot decode image")) << msg;
  // 8-bit depth.
  ASSERT_TRUE(cv::imwrite(depth_file(2).string(), cv::Mat(kH, kW, CV_8UC1, cv::Scalar(7))));
  msg = error_of([&] { (void)seq.load_rgbd(2, 5000.0); });
  EXPECT_TRUE(contains(msg, depth_file(2).string() + ": expected 16-bit depth PNG, got 8-bit")) << msg;
  // 16-bit but three channels.
  ASSERT_TRUE(cv::imwrite(depth_file(3).string(), cv::Mat(kH, kW, CV_16UC3, cv::Scalar(7, 7, 7))));
  msg = error_of([&] { (void)seq.load_rgbd(3, 5000.0); });
  EXPECT_TRUE(contains(msg, "expected 16-bit depth PNG, got 16-bit 3-channel")) << msg;
  // Size mismatch.
  ASSERT_TRUE(cv::imwrite(depth_file(4).string(), cv::Mat(24, 32, CV_16UC1, cv::Scalar(7))));
  msg = error_of([&] { (void)seq.load_rgbd(4, 5000.0); });
  EXPECT_TRUE(contains(msg, depth_file(4).string())) << msg;
  EXPECT_TRUE(contains(msg, "depth image size 32x24 does not match rgb image size 64x48")) << msg;
}

TEST_F(TumSequenceTest, PrefetchReturnsAllFramesInOrder) {
  const auto seq = TumSequence::open(dir_);
  FramePrefetcher prefetcher(seq, 5000.0, {.queue_depth = 2});
  EXPECT_EQ(prefetcher.size(), seq.size());
  for (std::size_t i = 0; i < seq.size(); ++i) {
    auto f = prefetcher.next();
    ASSERT_TRUE(f.has_value()) << i;
    EXPECT_EQ(f->index, i);
    EXPECT_DOUBLE_EQ(f->timestamp, kExpected[i].first);
    const auto direct = seq.load_rgbd(i, 5000.0);
    EXPECT_EQ(cv::norm(f->rgb, direct.rgb, cv::NORM_INF), 0.0) << i;
    EXPECT_EQ(cv::norm(f->depth, direct.depth, cv::NORM_INF), 0.0) << i;
  }
  EXPECT_FALSE(prefetcher.next().has_value());
  EXPECT_FALSE(prefetcher.next().has_value());
  const auto stats = prefetcher.stats();
  EXPECT_EQ(stats.frames, seq.size());
  EXPECT_GT(stats.decode_seconds, 0.0);
}

TEST_F(TumSequenceTest, PrefetchRangeAndEarlyShutdown) {
  const auto seq = TumSequence::open(dir_);
  {
    FramePrefetcher prefetcher(seq, 5000.0, {.queue_depth = 1, .begin = 1, .end = 3});
    EXPECT_EQ(prefetcher.next()->index, 1u);
    EXPECT_EQ(prefetcher.next()->index, 2u);
    EXPECT_FALSE(prefetcher.next().has_value());
  }
  {
    // Destroyed with frames still to decode: must not hang.
    FramePrefetcher prefetcher(seq, 5000.0, {.queue_depth = 1});
    EXPECT_EQ(prefetcher.next()->index, 0u);
  }
  EXPECT_THROW(FramePrefetcher(seq, 5000.0, {.queue_depth = 0}), lrd::Error);
}

// --preload: everything decoded before the first frame is taken, then delivered in order.
TEST_F(TumSequenceTest, PreloadDecodesEveryFrameFirst) {
  const auto seq = TumSequence::open(dir_);
  FramePrefetcher prefetcher(seq, 5000.0, {.queue_depth = seq.size()});
  prefetcher.wait_until_decoded();
  EXPECT_EQ(prefetcher.stats().frames, seq.size());
  for (std::size_t i = 0; i < seq.size(); ++i) EXPECT_EQ(prefetcher.next()->index, i);
  EXPECT_FALSE(prefetcher.next().has_value());
  prefetcher.wait_until_decoded();  // returns at once when done

  // A corrupt frame ends the preload (no hang); the frames before it come out, then the error.
  std::ofstream(depth_file(2), std::ios::binary) << "garbage";
  FramePrefetcher broken(seq, 5000.0, {.queue_depth = seq.size()});
  broken.wait_until_decoded();
  EXPECT_EQ(broken.stats().frames, 2u);
  EXPECT_EQ(broken.next()->index, 0u);
  EXPECT_EQ(broken.next()->index, 1u);
  EXPECT_TRUE(contains(error_of([&] { (void)broken.next(); }), depth_file(2).string()))
      << "corrupt frame named";
}

TEST_F(TumSequenceTest, PrefetchSurfacesCorruptPng) {
  const auto seq = TumSequence::open(dir_);
  std::ofstream(depth_file(2), std::ios::binary) << "not a png at all, just garbage bytes";
  FramePrefetcher prefetcher(seq, 5000.0);
  EXPECT_EQ(prefetcher.next()->index, 0u);
  EXPECT_EQ(prefetcher.next()->index, 1u);
  for (int attempt = 0; attempt < 2; ++attempt) {  // and again on a later call
    const std::string msg = error_of([&] { (void)prefetcher.next(); });
    EXPECT_TRUE(contains(msg, depth_file(2).string() + ": cannot decode image")) << msg;
  }
  EXPECT_EQ(prefetcher.stats().frames, 2u);
}
