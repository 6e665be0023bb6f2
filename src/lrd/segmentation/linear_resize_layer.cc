#include "lrd/segmentation/linear_resize_layer.h"

#include <algorithm>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "lrd/segmentation/layer_data.h"

namespace lrd::segmentation {

namespace {

// x2 with half-pixel centres: output 2i samples the input at i - 1/4, 2i + 1 at i + 1/4, both
// clamped to the border (cv::resize INTER_LINEAR's weights 3/4 and 1/4); rows first, then columns.
void upsample_x2(const float* in, int h, int w, float* out, std::vector<float>& rows) {
  const int ow = 2 * w;
  rows.resize(static_cast<std::size_t>(h) * ow);
  for (int y = 0; y < h; ++y) {
    const float* s = in + static_cast<std::size_t>(y) * w;
    float* d = rows.data() + static_cast<std::size_t>(y) * ow;
    // The border columns clamp; the loop between them has no branch.
    d[0] = 0.25f * s[0] + 0.75f * s[0];
    for (int x = 1; x < w; ++x) {
      d[2 * x - 1] = 0.75f * s[x - 1] + 0.25f * s[x];
      d[2 * x] = 0.25f * s[x - 1] + 0.75f * s[x];
    }
    d[2 * w - 1] = 0.75f * s[w - 1] + 0.25f * s[w - 1];
  }
  for (int y = 0; y < h; ++y) {
    const float* __restrict above = rows.data() + static_cast<std::size_t>(std::max(y - 1, 0)) * ow;
    const float* __restrict mid = rows.data() + static_cast<std::size_t>(y) * ow;
    const float* __restrict below = rows.data() + static_cast<std::size_t>(std::min(y + 1, h - 1)) * ow;
    float* __restrict top = out + static_cast<std::size_t>(2 * y) * ow;
    float* __restrict bottom = top + ow;
    for (int x = 0; x < ow; ++x) {
      top[x] = 0.25f * above[x] + 0.75f * mid[x];
      bottom[x] = 0.75f * mid[x] + 0.25f * below[x];
    }
  }
}

}  // namespace

LinearResizeLayer::LinearResizeLayer(const cv::dnn::LayerParams& params) {
  setParamsFrom(params);
  type = "LinearResize";  // not "Resize": nothing takes it for OpenCV's class
  out_h_ = params.get<int>("height");
  out_w_ = params.get<int>("width");
}

bool LinearResizeLayer::handles(const cv::dnn::LayerParams& params) {
  if (!params.has("height") || !params.has("width") || params.get<bool>("align_corners", false)) return false;
  const std::string interpolation = params.get<std::string>("interpolation", "");
  return interpolation == "opencv_linear" ||
         (interpolation == "bilinear" && params.get<bool>("half_pixel_centers", false));
}

bool LinearResizeLayer::supportBackend(int backend_id) {
  return backend_id == cv::dnn::DNN_BACKEND_OPENCV;
}

bool LinearResizeLayer::getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs,
                                        int /*required_outputs*/, std::vector<cv::dnn::MatShape>& outputs,
                                        std::vector<cv::dnn::MatShape>& /*internals*/) const {
  CV_Assert(!inputs.empty() && inputs[0].size() == 4);
  outputs.assign(1, cv::dnn::MatShape{inputs[0][0], inputs[0][1], out_h_, out_w_});
  return false;
}

void LinearResizeLayer::forward(cv::InputArrayOfArrays inputs_arr, cv::OutputArrayOfArrays outputs_arr,
                                cv::OutputArrayOfArrays /*internals*/) {
  LayerBlobs blobs = blobs_of(inputs_arr, outputs_arr);
  const cv::Mat& in = blobs.in;
  cv::Mat& out = blobs.out;
  const int h = in.size[2], w = in.size[3];
  const int planes = in.size[0] * in.size[1];
  const std::size_t in_plane = static_cast<std::size_t>(h) * w;
  const std::size_t out_plane = static_cast<std::size_t>(out_h_) * out_w_;
  const bool x2 = out_h_ == 2 * h && out_w_ == 2 * w;
  const float* src = in.ptr<float>();
  float* dst = out.ptr<float>();
  cv::parallel_for_(cv::Range(0, planes), [&](const cv::Range& r) {
    std::vector<float> rows;
    for (int p = r.start; p < r.end; ++p) {
      if (x2) {
        upsample_x2(src + p * in_plane, h, w, dst + p * out_plane, rows);
        continue;
      }
      const cv::Mat from(h, w, CV_32F, const_cast<float*>(src + p * in_plane));
      cv::Mat to(out_h_, out_w_, CV_32F, dst + p * out_plane);
      cv::resize(from, to, to.size(), 0, 0, cv::INTER_LINEAR);
    }
  });
}

}  // namespace lrd::segmentation
