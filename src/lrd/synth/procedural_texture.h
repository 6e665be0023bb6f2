#pragma once
// Procedural materials for the synthetic room and its people. All are deterministic in `seed`.
#include <cstdint>
#include <opencv2/core.hpp>

namespace lrd::synth::procedural {

cv::Mat value_noise(int size, int cell, std::uint64_t seed);  // CV_32F in [0,1], tileable
cv::Mat brick(int size, std::uint64_t seed);
cv::Mat plaster(int size, const cv::Scalar& bgr, std::uint64_t seed);
cv::Mat carpet(int size, const cv::Scalar& bgr, std::uint64_t seed);
cv::Mat plaid(int size, const cv::Scalar& a, const cv::Scalar& b, std::uint64_t seed);
cv::Mat stripes(int size, const cv::Scalar& a, const cv::Scalar& b, std::uint64_t seed);
cv::Mat denim(int size, const cv::Scalar& bgr, std::uint64_t seed);
cv::Mat skin(int size, const cv::Scalar& bgr, std::uint64_t seed);
cv::Mat hair(int size, const cv::Scalar& bgr, std::uint64_t seed);
cv::Mat book_spines(int size, std::uint64_t seed);
cv::Mat ceiling_tiles(int size, std::uint64_t seed);
cv::Mat cardboard(int size, std::uint64_t seed);

}  // namespace lrd::synth::procedural
