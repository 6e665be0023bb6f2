#pragma once
// Reading an image file with errors that name it, and nothing printed behind our back: a PNG's
// structure (chunk lengths, CRCs, the IHDR size, the IEND end) is checked before the decoder sees
// it, because libpng reports a damaged file on stderr itself before OpenCV returns an empty image.
#include <filesystem>
#include <opencv2/core.hpp>

namespace lrd::io {

// Images larger than this on either side are no camera frame (and would cost gigabytes).
inline constexpr int kMaxImageSide = 16384;

// cv::imread flags. Throws lrd::Error "FILE: problem" for a missing, unreadable, damaged or
// absurdly large file.
[[nodiscard]] cv::Mat read_image_file(const std::filesystem::path& file, int flags);

}  // namespace lrd::io
