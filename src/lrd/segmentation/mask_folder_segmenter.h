#pragma once
// `masks` backend: per-frame mask PNGs from a folder, named by the frame's timestamp as TUM names
// its images ("1305031102.175304.png") — the synthetic benchmark's ground truth (mask/), or
// masks a network computed earlier (a cache, as DynaSLAM keeps). The folder is indexed once; a
// frame takes the mask whose name is nearest its timestamp within a tolerance.
#include <map>

#include "lrd/segmentation/segmentation_params.h"
#include "lrd/segmentation/segmenter.h"

namespace lrd::segmentation {

class MaskFolderSegmenter : public Segmenter {
 public:
  // Throws lrd::Error naming the folder when it is missing or holds no timestamp-named PNG.
  explicit MaskFolderSegmenter(const MaskFolderParams& params);

  // Throws lrd::Error naming the frame's timestamp (no mask near it) or the file (unreadable,
  // not 8-bit single-channel, or of another size than the image).
  [[nodiscard]] cv::Mat segment(const cv::Mat& rgb, bool rgb_order, double timestamp) override;
  [[nodiscard]] std::string describe() const override;

  [[nodiscard]] std::size_t size() const { return files_.size(); }

 private:
  MaskFolderParams params_;
  std::map<double, std::filesystem::path> files_;  // timestamp -> file
  std::vector<unsigned char> is_dynamic_;          // per pixel value
};

}  // namespace lrd::segmentation
