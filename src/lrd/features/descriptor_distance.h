#pragma once
// Hamming distance between two 256-bit ORB descriptors (rows of 32 CV_8U).
#include <bit>
#include <cstdint>
#include <cstring>
#include <opencv2/core.hpp>

namespace lrd::features {

inline int descriptor_distance(const std::uint8_t* a, const std::uint8_t* b) {
  int d = 0;
  for (int i = 0; i < 32; i += 8) {
    std::uint64_t x, y;
    std::memcpy(&x, a + i, 8);
    std::memcpy(&y, b + i, 8);
    d += std::popcount(x ^ y);
  }
  return d;
}

inline int descriptor_distance(const cv::Mat& a, const cv::Mat& b) {
  return descriptor_distance(a.ptr(), b.ptr());
}

}  // namespace lrd::features
