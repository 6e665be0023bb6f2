#pragma once
// Background repair (paper §2.7, last paragraph; Fig. 12): the pixels of a keyframe hidden by
// people are filled with what earlier keyframes saw there. The static pixels (each source's own
// dynamic mask excluded) of the sources are projected with their depth into the target keyframe;
// only pixels inside the target's dynamic region are written, and the nearest surface wins
// (z-buffer), so the background comes back with its real colour and depth. Pixels no source saw
// stay invalid (depth 0, black) and are counted.
#include <vector>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/dense/dense_params.h"
#include "lrd/dense/rgbd_view.h"

namespace lrd::dense {

struct RepairResult {
  cv::Mat bgr;     // the target's colour with its dynamic region repaired (unfilled pixels black)
  cv::Mat depth;   // the same for depth (unfilled pixels 0)
  cv::Mat filled;  // CV_8UC1: 255 where a dynamic pixel was filled
  int dynamic_pixels = 0;
  int filled_pixels = 0;
  [[nodiscard]] double fill_ratio() const {
    return dynamic_pixels == 0 ? 1.0 : static_cast<double>(filled_pixels) / dynamic_pixels;
  }
};

class BackgroundRepairer {
 public:
  BackgroundRepairer(const camera::PinholeCamera& camera, const RepairParams& params);

  // Repairs `target` from `sources` (any order; poses in the same world frame). Without a dynamic
  // region the result is a copy of the target.
  [[nodiscard]] RepairResult repair(const RgbdView& target,
                                    const std::vector<const RgbdView*>& sources) const;

 private:
  // The part of a source image (size `size`, pose T_st relative to the target) that can project
  // into the target rectangle `box`.
  [[nodiscard]] cv::Rect source_window(const cv::Rect& box, const Eigen::Isometry3d& T_st,
                                       const cv::Size& size) const;

  camera::PinholeCamera camera_;
  RepairParams params_;
};

}  // namespace lrd::dense
