#pragma once
// Reading an image file with errors that name it, and nothing printed behind our back: a PNG's
// structure (chunk lengths, CRCs, the IHDR size, the IEND end) is checked before the decoder sees
// it, because libpng reports a damaged file on stderr itself before OpenCV returns an empty image.
// Writing one whole or not at all (util::AtomicFile).
#include <filesystem>
#include <opencv2/core.hpp>
#include <vector>

#include "lrd/util/atomic_file.h"

namespace lrd::io {

// Images larger than this on either side are no camera frame (and would cost gigabytes).
inline constexpr int kMaxImageSide = 16384;

// cv::imread flags. Throws lrd::Error "FILE: problem" for a missing, unreadable, damaged or
// absurdly large file.
[[nodiscard]] cv::Mat read_image_file(const std::filesystem::path& file, int flags);

// Encodes the image as cv::imwrite would (the format from the file's extension, cv::IMWRITE_*
// params: the same bytes) and writes it through util::AtomicFile. Throws lrd::Error "FILE: problem"
// when it cannot be encoded or written.
void write_image_file(const std::filesystem::path& file, const cv::Mat& image,
                      const std::vector<int>& params = {}, util::Sync sync = util::Sync::yes);

}  // namespace lrd::io
