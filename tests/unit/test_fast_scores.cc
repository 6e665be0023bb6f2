// FAST scores computed once per level: the corners read from them at any threshold and in any
// region are OpenCV's cv::FAST(TYPE_9_16, non-maximum suppression) on that region, bit for bit.
#include <gtest/gtest.h>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "lrd/features/fast_scores.h"
#include "lrd/util/cpu_features.h"

using lrd::features::FastScores;

namespace {

// Blobs and edges at a few scales, with per-pixel noise as a Kinect's colour camera adds: many
// corners, weak ones, ties between neighbours.
cv::Mat textured(cv::Size size, double blur, double noise, unsigned seed) {
  cv::RNG rng(seed);
  cv::Mat base(size, CV_32F), grain(size, CV_32F);
  rng.fill(base, cv::RNG::UNIFORM, 0.0, 255.0);
  if (blur > 0) cv::GaussianBlur(base, base, cv::Size(), blur);
  cv::normalize(base, base, 0, 255, cv::NORM_MINMAX);
  rng.fill(grain, cv::RNG::NORMAL, 0.0, noise);
  cv::Mat out;
  cv::Mat(base + grain).convertTo(out, CV_8U);  // saturates at 0 and 255
  return out;
}

// What cv::FAST finds in `region` (it reads 3 pixels around it), in image coordinates.
std::vector<cv::KeyPoint> opencv_fast(const cv::Mat& image, const cv::Rect& region, int threshold) {
  const cv::Rect grown(region.x - 3, region.y - 3, region.width + 6, region.height + 6);
  std::vector<cv::KeyPoint> found;
  cv::FAST(image(grown), found, threshold, true, cv::FastFeatureDetector::TYPE_9_16);
  for (cv::KeyPoint& kp : found)
    kp.pt += cv::Point2f(static_cast<float>(grown.x), static_cast<float>(grown.y));
  return found;
}

// Number of keypoints that differ in any field (or in count) between the two lists.
int differences(const std::vector<cv::KeyPoint>& a, const std::vector<cv::KeyPoint>& b) {
  int wrong = std::abs(static_cast<int>(a.size()) - static_cast<int>(b.size()));
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    wrong += a[i].pt != b[i].pt || a[i].response != b[i].response || a[i].size != b[i].size ||
             a[i].angle != b[i].angle || a[i].octave != b[i].octave || a[i].class_id != b[i].class_id;
  return wrong;
}

}  // namespace

// Both copies of the loops (AVX2 where the CPU has it, and the SSE2 baseline) give the same corners.
class FastScoresCopies : public testing::TestWithParam<bool> {
 protected:
  void SetUp() override { lrd::util::use_baseline_copies_only(GetParam()); }
  void TearDown() override { lrd::util::use_baseline_copies_only(false); }
};
INSTANTIATE_TEST_SUITE_P(Copies, FastScoresCopies, testing::Values(false, true),
                         [](const testing::TestParamInfo<bool>& info) {
                           return info.param ? "Baseline" : "Native";
                         });

TEST_P(FastScoresCopies, CornersAreOpenCvsFastOverTheWholeAreaAtEveryThreshold) {
  FastScores scores;
  int compared = 0;
  for (const cv::Size size : {cv::Size(640, 480), cv::Size(157, 93), cv::Size(40, 30), cv::Size(9, 9)}) {
    for (const double blur : {0.0, 1.5, 4.0}) {
      const cv::Mat image = textured(size, blur, 3.0, 7 + size.width);
      const cv::Rect area(3, 3, size.width - 6, size.height - 6);  // as close to the border as FAST reads
      scores.compute(image, area, 7);
      for (const int threshold : {7, 8, 20, 40, 120, 255}) {
        SCOPED_TRACE(testing::Message() << size << " blur " << blur << " threshold " << threshold);
        std::vector<cv::KeyPoint> ours;
        scores.corners(area, threshold, ours);
        const std::vector<cv::KeyPoint> expected = opencv_fast(image, area, threshold);
        EXPECT_EQ(differences(ours, expected), 0);
        compared += static_cast<int>(expected.size());
      }
    }
  }
  EXPECT_GT(compared, 20000);  // the images hold corners at the thresholds compared
}

// Regions (the extractor's runs of weak cells): a corner on a region's edge is suppressed only by
// neighbours inside the region, as cv::FAST on the region alone; widths around the 32-pixel
// blocks and one-pixel strips included.
TEST_P(FastScoresCopies, CornersOfARegionAreOpenCvsFastOnThatRegion) {
  const cv::Mat image = textured(cv::Size(320, 240), 1.0, 4.0, 5);
  const cv::Rect area(19, 19, 320 - 38, 240 - 38);
  FastScores scores;
  scores.compute(image, area, 7);
  std::mt19937 rng(11);
  std::vector<cv::Rect> regions = {area,
                                   {19, 19, 1, 1},
                                   {19, 19, 282, 1},
                                   {19, 19, 1, 202},
                                   {40, 50, 33, 30},
                                   {40, 50, 34, 30},
                                   {40, 50, 35, 30},
                                   {40, 50, 66, 2},
                                   {300, 220, 1, 1}};
  for (int i = 0; i < 200; ++i) {
    const int x = std::uniform_int_distribution<int>(area.x, area.x + area.width - 1)(rng);
    const int y = std::uniform_int_distribution<int>(area.y, area.y + area.height - 1)(rng);
    const int w = std::uniform_int_distribution<int>(1, area.x + area.width - x)(rng);
    const int h = std::uniform_int_distribution<int>(1, std::min(60, area.y + area.height - y))(rng);
    regions.emplace_back(x, y, w, h);
  }
  int compared = 0;
  for (const cv::Rect& region : regions) {
    for (const int threshold : {7, 20}) {
      SCOPED_TRACE(testing::Message() << region << " threshold " << threshold);
      std::vector<cv::KeyPoint> ours;
      scores.corners(region, threshold, ours);
      const std::vector<cv::KeyPoint> expected = opencv_fast(image, region, threshold);
      ASSERT_EQ(differences(ours, expected), 0);
      compared += static_cast<int>(expected.size());
    }
  }
  EXPECT_GT(compared, 5000);
}

// Corners are appended: the extractor reads a level's strong corners and then its weak cells'
// into the same list.
TEST(FastScores, CornersAreAppendedAndBadRequestsAreRefused) {
  const cv::Mat image = textured(cv::Size(100, 80), 1.0, 3.0, 3);
  const cv::Rect area(3, 3, 94, 74);
  FastScores scores;
  scores.compute(image, area, 10);
  std::vector<cv::KeyPoint> both;
  scores.corners(cv::Rect(3, 3, 94, 30), 20, both);
  const std::size_t first = both.size();
  ASSERT_GT(first, 0u);
  scores.corners(cv::Rect(3, 40, 94, 30), 20, both);
  EXPECT_GT(both.size(), first);
  EXPECT_EQ(differences(std::vector<cv::KeyPoint>(both.begin() + static_cast<long>(first), both.end()),
                        opencv_fast(image, cv::Rect(3, 40, 94, 30), 20)),
            0);
  std::vector<cv::KeyPoint> out;
  EXPECT_THROW(scores.corners(area, 9, out), cv::Exception);                      // under the floor
  EXPECT_THROW(scores.corners(cv::Rect(0, 0, 10, 10), 20, out), cv::Exception);   // outside the area
  EXPECT_THROW(scores.compute(image, cv::Rect(2, 3, 10, 10), 7), cv::Exception);  // FAST reads outside
}
