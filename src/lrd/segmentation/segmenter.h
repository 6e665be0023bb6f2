#pragma once
// One interface for every way of telling dynamic pixels from static ones (paper §2.6): a network
// through OpenCV DNN (`onnx`), masks computed earlier or ground truth (`masks`), or nothing.
#include <opencv2/core.hpp>
#include <string>

namespace lrd::segmentation {

class Segmenter {
 public:
  virtual ~Segmenter() = default;
  // Dynamic-pixel mask of one colour image: CV_8UC1 of the image's size, 255 = dynamic, 0 =
  // static. `rgb` is CV_8UC3 in the order `rgb_order` says (true: RGB, false: BGR) or CV_8UC1.
  // Throws lrd::Error when the image cannot be segmented (e.g. a mask file is missing).
  [[nodiscard]] virtual cv::Mat segment(const cv::Mat& rgb, bool rgb_order, double timestamp) = 0;
  // "onnx (models/fnet-lite.onnx)", "masks (seq/mask)": for logs and summaries.
  [[nodiscard]] virtual std::string describe() const = 0;
};

}  // namespace lrd::segmentation
