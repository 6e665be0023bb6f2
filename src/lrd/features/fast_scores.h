#pragma once
// FAST-9/16 corner scores of every pixel of an area (Rosten and Drummond 2006), computed once per
// pyramid level and read at both of the extractor's thresholds. The corners are those of OpenCV's
// cv::FAST(TYPE_9_16, non-maximum suppression) bit for bit: same pixels, order and responses.
// OpenCV's FAST tests each pixel at one threshold and scores the corners one by one; run twice
// (the high threshold over the level, the low one over the cells left without a corner) it was
// two thirds of our extraction under the `tum` realism profile, where sensor noise makes many
// candidates (bench/results/log/performance.md, 2026-12-07: "FAST scored once per level").
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace lrd::features {

class FastScores {
 public:
  // Scores every pixel of `area`, which must lie 3 pixels or more inside `image` (CV_8UC1). A
  // pixel's score s is the largest contrast by which a contiguous arc of 9 of its 16 circle pixels
  // are all brighter, or all darker, than it (0 if none): it is a corner at threshold t iff s > t,
  // and OpenCV's cornerScore is s - 1. Scores up to `floor` may read 0 (most pixels are skipped
  // that way), so corners() takes thresholds of `floor` or more.
  void compute(const cv::Mat& image, const cv::Rect& area, int floor);

  // Appends the corners at `threshold` (>= 1 and >= compute()'s floor) inside `region` (a part of the scored
  // area) whose score beats every neighbour in `region` that is a corner too, in row-major order, with
  // response s - 1 and OpenCV's size 7: what cv::FAST(image(region grown by 3 pixels),
  // threshold, true) finds, shifted to image coordinates.
  void corners(const cv::Rect& region, int threshold, std::vector<cv::KeyPoint>& out);

 private:
  cv::Mat scores_;  // CV_8U, area-sized
  cv::Rect area_;
  int floor_ = 0;
  std::vector<std::uint8_t> buffer_;  // corners()' rows, kept between calls
};

}  // namespace lrd::features
