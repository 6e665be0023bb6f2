// The dynamic front end's async schedule: frames the network is not given take the newest mask,
// carried over with the depth the front end kept of the mask's own frame.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/dynamic/dynamic_front_end.h"
#include "temp_dir.h"

namespace {

std::string timestamp_name(double t) {
  char name[64];
  std::snprintf(name, sizeof(name), "%.6f.png", t);
  return name;
}

}  // namespace

// Stride 2: the network sees the even frames (each waits for its own mask here, so that the test
// does not race the segmentation thread) and only their depth is kept; an odd frame takes the
// previous frame's mask moved along the predicted pose: the camera 0.2 m to the right at 2 m from
// the wall shifts it 53.5 pixels to the left, which only the carry-over with frame k's depth does.
TEST(DynamicFrontEnd, OddFramesCarryTheEvenFramesMasksWithTheirKeptDepth) {
  lrd::test::TempDir tmp("front_end");
  const lrd::camera::PinholeCamera camera;  // 640x480, fx 535.4
  cv::Mat person = cv::Mat::zeros(camera.height, camera.width, CV_8UC1);
  person(cv::Rect(200, 150, 100, 100)).setTo(255);
  constexpr int kFrames = 8;
  auto timestamp = [](int i) { return 1.0 + 0.033 * i; };
  for (int i = 0; i < kFrames; ++i)
    ASSERT_TRUE(cv::imwrite((tmp.path() / timestamp_name(timestamp(i))).string(), person));

  lrd::dynamic::DynamicParams params;
  params.mode = lrd::dynamic::DynamicMode::Semantic;
  lrd::segmentation::SegmentationParams segmentation;
  segmentation.backend = lrd::segmentation::Backend::Masks;
  segmentation.masks.folder = tmp.path();
  segmentation.schedule = lrd::segmentation::Schedule::Async;
  segmentation.stride = 2;
  segmentation.max_wait_ms = 5000.0;
  lrd::dynamic::DynamicFrontEnd front_end(params, segmentation, camera);

  const cv::Mat rgb = cv::Mat::zeros(camera.height, camera.width, CV_8UC3);
  const cv::Mat depth(camera.height, camera.width, CV_32FC1, cv::Scalar(2.0f));
  Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
  moved.translation() = Eigen::Vector3d(-0.2, 0.0, 0.0);  // T_cw of a camera 0.2 m to the right
  for (int i = 0; i < kFrames; ++i) {
    SCOPED_TRACE(testing::Message() << "frame " << i);
    EXPECT_EQ(front_end.keeps_depth_of(static_cast<std::uint64_t>(i)), i % 2 == 0);
    front_end.submit(static_cast<std::uint64_t>(i), timestamp(i), rgb);
    const auto mask = front_end.mask(static_cast<std::uint64_t>(i), depth, moved);
    ASSERT_FALSE(mask.mask.empty());
    if (i % 2 == 0) {
      EXPECT_EQ(mask.mask_age, 0);
      EXPECT_NE(mask.mask.at<std::uint8_t>(200, 290), 0);  // its own mask (columns 200-299), dilated
      EXPECT_EQ(mask.mask.at<std::uint8_t>(200, 150), 0);
    } else {
      EXPECT_EQ(mask.mask_age, 1);
      EXPECT_EQ(mask.mask_frame, i - 1);
      // Carried over: columns 146-246, dilated by 7 + 4 pixels.
      EXPECT_NE(mask.mask.at<std::uint8_t>(200, 150), 0);
      EXPECT_EQ(mask.mask.at<std::uint8_t>(200, 290), 0);
    }
    front_end.frame_done(static_cast<std::uint64_t>(i), Eigen::Isometry3d::Identity());
  }
  front_end.shutdown();
}
