#pragma once
// `onnx` backend: any segmentation network exported to ONNX, run by OpenCV DNN (no Python, no
// ONNX Runtime). Pre-processing, output layout and the dynamic classes come from the config, and
// the model is checked against them at start-up with one forward pass, so a model with the wrong
// output shape is refused before the first frame, with both shapes in the message.
#include <opencv2/dnn.hpp>

#include "lrd/segmentation/segmentation_params.h"
#include "lrd/segmentation/segmenter.h"

namespace lrd::segmentation {

class OnnxSegmenter : public Segmenter {
 public:
  // Throws lrd::Error naming the model file when it is missing, unreadable or its output does
  // not fit `params`.
  explicit OnnxSegmenter(const OnnxParams& params);

  [[nodiscard]] cv::Mat segment(const cv::Mat& rgb, bool rgb_order, double timestamp) override;
  [[nodiscard]] std::string describe() const override;

  // Per-pixel class index at the image's size (CV_8UC1; probability layout: 1 above threshold,
  // else 0). Logits are arg-maxed at the network's resolution (with `upsample_logits`, at its
  // input resolution after a bilinear resize), then resized nearest-neighbour; probabilities are
  // resized bilinearly, then thresholded. segment() takes a cheaper route to the same decision.
  [[nodiscard]] cv::Mat labels(const cv::Mat& rgb, bool rgb_order);
  // The network's raw output for one image (N x C x H x W as the model gives it).
  [[nodiscard]] cv::Mat forward(const cv::Mat& rgb, bool rgb_order);

  [[nodiscard]] const OnnxParams& params() const { return params_; }

 private:
  [[nodiscard]] cv::Mat blob(const cv::Mat& rgb, bool rgb_order) const;
  // Checks the output of one forward pass against the config; returns its (C, H, W).
  void check_output(const cv::Mat& out);
  // 255 where the arg-max class of 1 x C x h x w logits is dynamic, at `image_size`.
  [[nodiscard]] cv::Mat dynamic_from_logits(const cv::Mat& out, cv::Size image_size) const;

  OnnxParams params_;
  cv::dnn::Net net_;
  std::vector<unsigned char> is_dynamic_;  // per class index
};

}  // namespace lrd::segmentation
