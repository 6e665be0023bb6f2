#include "lrd/segmentation/onnx_segmenter.h"

#include <fmt/format.h>

#include <opencv2/imgproc.hpp>
#include <optional>

#include "lrd/segmentation/own_kernels.h"
#include "lrd/util/error.h"

namespace lrd::segmentation {

namespace {
std::string shape_of(const cv::Mat& m) {
  std::string s;
  for (int i = 0; i < m.dims; ++i) s += (i ? "x" : "") + std::to_string(m.size[i]);
  return s;
}

// Channel k of a 1 x C x H x W (or 1 x H x W) network output as an H x W view, no copy.
cv::Mat channel_plane(const cv::Mat& out, int k) {
  const int h = out.size[out.dims - 2], w = out.size[out.dims - 1];
  return {h, w, CV_32F, const_cast<float*>(out.ptr<float>()) + static_cast<std::size_t>(k) * h * w};
}
}  // namespace

OnnxSegmenter::OnnxSegmenter(const OnnxParams& params) : params_(params) {
  std::error_code ec;
  if (params_.model.empty()) throw Error("segmentation.onnx.model: no model file given");
  if (!std::filesystem::is_regular_file(params_.model, ec))
    throw file_error(params_.model, "segmentation model not found");
  // OpenCV creates the layers while it reads the model (and the rest at the first forward pass):
  // both inside the scope.
  std::optional<OwnKernelsScope> own_kernels;
  if (params_.own_kernels) own_kernels.emplace();
  try {
    net_ = cv::dnn::readNetFromONNX(params_.model.string());
  } catch (const cv::Exception& e) {
    throw file_error(params_.model, std::string("OpenCV DNN cannot read this ONNX model: ") + e.err);
  }
  if (net_.empty()) throw file_error(params_.model, "OpenCV DNN read an empty network");
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  is_dynamic_.assign(std::max<std::size_t>(params_.classes.size(), 1), 0);
  for (int id : params_.dynamic_ids) {
    if (id < 0 || static_cast<std::size_t>(id) >= is_dynamic_.size())
      throw file_error(params_.model, fmt::format("dynamic class index {} is not among the {} classes", id,
                                                  params_.classes.size()));
    is_dynamic_[static_cast<std::size_t>(id)] = 1;
  }
  // One forward pass on a grey image: the output must fit the configured layout.
  const cv::Mat probe(params_.input_height, params_.input_width, CV_8UC3, cv::Scalar(128, 128, 128));
  check_output(forward(probe, true));
}

std::string OnnxSegmenter::describe() const {
  return "onnx (" + params_.model.string() + ")";
}

cv::Mat OnnxSegmenter::blob(const cv::Mat& rgb, bool rgb_order) const {
  // Resize first: every later step then works on the network's few pixels, not the camera's.
  cv::Mat resized;
  cv::resize(rgb, resized, cv::Size(params_.input_width, params_.input_height), 0, 0, cv::INTER_LINEAR);
  if (resized.channels() == 1) cv::cvtColor(resized, resized, cv::COLOR_GRAY2BGR);
  const bool swap = rgb.channels() == 3 && rgb_order != params_.input_rgb;
  const auto& m = params_.mean;
  const auto& sd = params_.std;
  if (sd[0] == sd[1] && sd[1] == sd[2]) {
    // (x * scale - mean) / std = (x - mean / scale) * (scale / std): one pass in blobFromImage,
    // whose mean is given in the image's channel order (before the swap).
    const double k = params_.scale / sd[0];
    cv::Scalar mean(m[0] / params_.scale, m[1] / params_.scale, m[2] / params_.scale);
    if (swap) std::swap(mean[0], mean[2]);
    return cv::dnn::blobFromImage(resized, k, cv::Size(), mean, swap, false, CV_32F);
  }
  if (swap) cv::cvtColor(resized, resized, cv::COLOR_BGR2RGB);  // swaps R and B
  cv::Mat f;
  resized.convertTo(f, CV_32FC3, params_.scale);
  cv::subtract(f, cv::Scalar(m[0], m[1], m[2]), f);
  cv::multiply(f, cv::Scalar(1.0 / sd[0], 1.0 / sd[1], 1.0 / sd[2]), f);
  return cv::dnn::blobFromImage(f, 1.0, cv::Size(), cv::Scalar(), false, false, CV_32F);
}

cv::Mat OnnxSegmenter::forward(const cv::Mat& rgb, bool rgb_order) {
  net_.setInput(blob(rgb, rgb_order));
  try {
    return net_.forward().clone();
  } catch (const cv::Exception& e) {
    throw file_error(params_.model, std::string("forward pass failed: ") + e.err);
  }
}

void OnnxSegmenter::check_output(const cv::Mat& out) {
  const int classes = static_cast<int>(params_.classes.size());
  const bool four_d = out.dims == 4 && out.size[0] == 1;
  const bool three_d = out.dims == 3 && out.size[0] == 1;
  std::string expected;
  bool ok = false;
  switch (params_.output) {
    case OutputLayout::Logits:
      expected = fmt::format("1x{}xHxW class scores", classes);
      ok = four_d && out.size[1] == classes;
      break;
    case OutputLayout::Probability:
      expected = "1x1xHxW probability";
      ok = (four_d && out.size[1] == 1) || three_d;
      break;
    case OutputLayout::Labels:
      expected = "1x1xHxW or 1xHxW class indices";
      ok = (four_d && out.size[1] == 1) || three_d;
      break;
  }
  if (!ok)
    throw file_error(params_.model, fmt::format("output shape {} does not fit the config (expected {})",
                                                shape_of(out), expected));
}

cv::Mat OnnxSegmenter::labels(const cv::Mat& rgb, bool rgb_order) {
  const cv::Mat out = forward(rgb, rgb_order);
  const int h = out.size[out.dims - 2], w = out.size[out.dims - 1];
  const cv::Size image_size = rgb.size();
  cv::Mat small(h, w, CV_8UC1);
  if (params_.output == OutputLayout::Probability) {
    const cv::Mat prob = channel_plane(out, 0);
    cv::Mat full;
    cv::resize(prob, full, image_size, 0, 0, cv::INTER_LINEAR);
    cv::Mat label = full > params_.threshold;  // 255 / 0
    return label / 255;
  }
  if (params_.output == OutputLayout::Labels) {
    const cv::Mat lab = channel_plane(out, 0);
    lab.convertTo(small, CV_8U);
  } else {
    // Logits coarser than the network input (fnet-lite gives H/2) are first brought to the input
    // size bilinearly, as its training loss does; then arg-max, one vectorised pass per class
    // (strict >: the first of tied classes wins, like a per-pixel arg-max).
    const cv::Size in_size(params_.input_width, params_.input_height);
    const bool upsample = params_.upsample_logits && h < in_size.height && w < in_size.width;
    const cv::Size size = upsample ? in_size : cv::Size(w, h);
    small.create(size, CV_8UC1);
    small.setTo(0);
    cv::Mat best, plane, better;
    for (int k = 0; k < out.size[1]; ++k) {
      const cv::Mat raw = channel_plane(out, k);
      if (upsample)
        cv::resize(raw, plane, size, 0, 0, cv::INTER_LINEAR);
      else
        plane = raw;
      if (k == 0) {
        plane.copyTo(best);
        continue;
      }
      cv::compare(plane, best, better, cv::CMP_GT);
      small.setTo(k, better);
      cv::max(best, plane, best);
    }
  }
  cv::Mat full;
  cv::resize(small, full, image_size, 0, 0, cv::INTER_NEAREST);
  return full;
}

cv::Mat OnnxSegmenter::segment(const cv::Mat& rgb, bool rgb_order, double /*timestamp*/) {
  if (params_.output == OutputLayout::Probability) {
    // Straight to 0/255: the same pixels as labels(), without its 0/1 detour over the full image.
    const cv::Mat out = forward(rgb, rgb_order);
    cv::Mat full;
    cv::resize(channel_plane(out, 0), full, rgb.size(), 0, 0, cv::INTER_LINEAR);
    return full > params_.threshold;
  }
  if (params_.output == OutputLayout::Logits) return dynamic_from_logits(forward(rgb, rgb_order), rgb.size());
  const cv::Mat label = labels(rgb, rgb_order);
  cv::Mat mask(label.size(), CV_8UC1);
  const std::size_t n = label.total();
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned l = label.data[i];
    mask.data[i] = (l < is_dynamic_.size() && is_dynamic_[l]) ? 255 : 0;
  }
  return mask;
}

cv::Mat OnnxSegmenter::dynamic_from_logits(const cv::Mat& out, cv::Size image_size) const {
  // The mask only asks "is the arg-max class dynamic?": best dynamic score minus best static score,
  // one vectorised max per class plane instead of a per-pixel arg-max over all classes. At the
  // network's pixels that is the arg-max decision (an exact tie counts as static); between them the
  // margin is interpolated bilinearly, which keeps object outlines smooth when the network's output
  // is coarser than the image (fnet-lite gives H/2).
  const int c = out.size[1];
  cv::Mat best_dynamic, best_static;
  for (int k = 0; k < c; ++k) {
    cv::Mat& best = (k < static_cast<int>(is_dynamic_.size()) && is_dynamic_[k]) ? best_dynamic : best_static;
    if (best.empty())
      channel_plane(out, k).copyTo(best);
    else
      cv::max(best, channel_plane(out, k), best);
  }
  if (best_dynamic.empty()) return cv::Mat::zeros(image_size, CV_8UC1);
  if (best_static.empty()) return cv::Mat(image_size, CV_8UC1, cv::Scalar(255));
  cv::Mat margin = best_dynamic - best_static;
  if (margin.size() != image_size) cv::resize(margin, margin, image_size, 0, 0, cv::INTER_LINEAR);
  return margin > 0.0f;
}

}  // namespace lrd::segmentation
