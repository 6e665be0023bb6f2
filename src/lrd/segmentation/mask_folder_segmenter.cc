#include "lrd/segmentation/mask_folder_segmenter.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "lrd/io/image_file.h"
#include "lrd/util/error.h"

namespace lrd::segmentation {

namespace fs = std::filesystem;

MaskFolderSegmenter::MaskFolderSegmenter(const MaskFolderParams& params) : params_(params) {
  std::error_code ec;
  if (params_.folder.empty()) throw Error("segmentation.masks.folder: no mask folder given");
  if (!fs::is_directory(params_.folder, ec)) throw file_error(params_.folder, "mask folder not found");
  for (const auto& entry : fs::directory_iterator(params_.folder, ec)) {
    if (entry.path().extension() != ".png") continue;
    const std::string stem = entry.path().stem().string();
    double t = 0.0;
    const auto [end, err] = std::from_chars(stem.data(), stem.data() + stem.size(), t);
    if (err != std::errc() || end != stem.data() + stem.size() || !std::isfinite(t))
      continue;  // not a timestamp
    files_.emplace(t, entry.path());
  }
  if (ec) throw file_error(params_.folder, "cannot list the mask folder: " + ec.message());
  if (files_.empty()) throw file_error(params_.folder, "no timestamp-named .png masks in this folder");
  is_dynamic_.assign(256, 0);
  if (params_.dynamic_values.empty()) {
    for (int v = 1; v < 256; ++v) is_dynamic_[static_cast<std::size_t>(v)] = 1;
  } else {
    for (int v : params_.dynamic_values)
      if (v >= 0 && v < 256) is_dynamic_[static_cast<std::size_t>(v)] = 1;
  }
}

std::string MaskFolderSegmenter::describe() const {
  return "masks (" + params_.folder.string() + ")";
}

cv::Mat MaskFolderSegmenter::segment(const cv::Mat& rgb, bool /*rgb_order*/, double timestamp) {
  // Nearest name in time.
  auto it = files_.lower_bound(timestamp);
  if (it == files_.end() ||
      (it != files_.begin() && timestamp - std::prev(it)->first < it->first - timestamp))
    it = std::prev(it);
  if (std::abs(it->first - timestamp) > params_.max_time_difference)
    throw file_error(params_.folder, fmt::format("no mask for the frame at {:.6f} (nearest: {})", timestamp,
                                                 it->second.filename().string()));
  const cv::Mat raw = io::read_image_file(it->second, cv::IMREAD_UNCHANGED);
  if (raw.type() != CV_8UC1)
    throw file_error(it->second, fmt::format("a mask must be an 8-bit single-channel PNG, got {}",
                                             cv::typeToString(raw.type())));
  if (raw.size() != rgb.size())
    throw file_error(it->second,
                     fmt::format("mask is {}x{}, the image {}x{}", raw.cols, raw.rows, rgb.cols, rgb.rows));
  cv::Mat mask(raw.size(), CV_8UC1);
  const std::size_t n = raw.total();
  const unsigned char* src = raw.ptr<unsigned char>();  // imread gives a continuous image
  for (std::size_t i = 0; i < n; ++i) mask.data[i] = is_dynamic_[src[i]] ? 255 : 0;
  return mask;
}

}  // namespace lrd::segmentation
