#include "lrd/io/image_file.h"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <new>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"

namespace lrd::io {

namespace {

constexpr std::array<unsigned char, 8> kPngSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

std::uint32_t big_endian_u32(const unsigned char* p) {
  return std::uint32_t{p[0]} << 24 | std::uint32_t{p[1]} << 16 | std::uint32_t{p[2]} << 8 |
         std::uint32_t{p[3]};
}

// Walks the chunks of a PNG file: each must fit in the file and match its CRC; the IHDR must
// come first with a size within kMaxImageSide; the file must reach IEND.
void check_png(const std::vector<unsigned char>& bytes, const std::filesystem::path& file) {
  std::size_t at = kPngSignature.size();
  bool first = true;
  for (;;) {
    if (bytes.size() - at < 12) throw file_error(file, "cannot decode image: truncated PNG (no IEND chunk)");
    const std::uint32_t length = big_endian_u32(&bytes[at]);
    if (length > bytes.size() - at - 12)
      throw file_error(file, "cannot decode image: truncated PNG (a chunk runs past the end)");
    const unsigned char* type = &bytes[at + 4];
    const unsigned char* data = type + 4;
    const std::uint32_t crc = big_endian_u32(data + length);
    const uLong computed = crc32(crc32(0L, Z_NULL, 0), type, static_cast<uInt>(length + 4));
    const std::string name(reinterpret_cast<const char*>(type), 4);
    if (computed != crc)
      throw file_error(file, "cannot decode image: corrupt PNG (CRC mismatch in the " + name + " chunk)");
    if (first) {
      if (name != "IHDR" || length != 13)
        throw file_error(file, "cannot decode image: corrupt PNG (no IHDR chunk first)");
      const std::uint32_t width = big_endian_u32(data), height = big_endian_u32(data + 4);
      if (width == 0 || height == 0)
        throw file_error(file,
                         "corrupt PNG (size " + std::to_string(width) + "x" + std::to_string(height) + ")");
      if (width > kMaxImageSide || height > kMaxImageSide)
        throw file_error(file, "image is " + std::to_string(width) + "x" + std::to_string(height) +
                                   ", larger than " + std::to_string(kMaxImageSide) +
                                   " on a side: not a camera frame");
      first = false;
    }
    at += 12 + length;
    if (name == "IEND") return;
  }
}

}  // namespace

cv::Mat read_image_file(const std::filesystem::path& file, int flags) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) {
    if (std::filesystem::exists(file, ec)) throw file_error(file, "not a regular file (a folder?)");
    throw file_error(file, "image file not found");
  }
  std::ifstream in(file, std::ios::binary);
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw file_error(file, "cannot read the file");
  if (bytes.empty()) throw file_error(file, "empty image file");
  const bool png = bytes.size() >= kPngSignature.size() &&
                   std::memcmp(bytes.data(), kPngSignature.data(), kPngSignature.size()) == 0;
  if (png) check_png(bytes, file);
  cv::Mat img;
  try {
    img = cv::imdecode(bytes, flags);
  } catch (const cv::Exception& e) {
    if (e.code == cv::Error::StsNoMem) throw std::bad_alloc();
    throw file_error(file, "cannot decode image (corrupt or unsupported file)");
  }
  if (img.empty()) {
    // The decoders report running out of memory as a failed decode: when not even the image's
    // worth of memory can be had (cv::Mat then throws OpenCV's out-of-memory error), that was the
    // cause, not the file.
    const std::size_t probe = std::clamp<std::size_t>(bytes.size() * 4, std::size_t{4} << 20, 1u << 30);
    const cv::Mat room(1, static_cast<int>(probe), CV_8UC1);
    throw file_error(file, "cannot decode image (corrupt or unsupported file)");
  }
  if (img.cols > kMaxImageSide || img.rows > kMaxImageSide)
    throw file_error(file, "image is " + std::to_string(img.cols) + "x" + std::to_string(img.rows) +
                               ", larger than " + std::to_string(kMaxImageSide) +
                               " on a side: not a camera frame");
  return img;
}

void write_image_file(const std::filesystem::path& file, const cv::Mat& image, const std::vector<int>& params,
                      util::Sync sync) {
  std::vector<unsigned char> bytes;
  bool ok = false;
  try {
    ok = cv::imencode(file.extension().string(), image, bytes, params);
  } catch (const cv::Exception& e) {
    throw file_error(file, fmt::format("cannot encode the image: {}", e.err));
  }
  if (!ok) throw file_error(file, "cannot encode the image");
  util::write_file_bytes(file, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                         sync);
}

}  // namespace lrd::io
