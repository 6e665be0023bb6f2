#pragma once
// What our layers (own_kernels.h) take from OpenCV: the weights and bias its importers hand to a
// layer constructor (LayerParams::blobs), as flat float arrays, and the one input and one output
// blob of a forward pass.
#include <opencv2/dnn.hpp>
#include <vector>

namespace lrd::segmentation {

// blobs[0], all of it, in its own order.
inline std::vector<float> weights_of(const cv::dnn::LayerParams& params) {
  const cv::Mat w = params.blobs[0].isContinuous() ? params.blobs[0] : params.blobs[0].clone();
  CV_Assert(w.depth() == CV_32F);
  return {w.ptr<float>(), w.ptr<float>() + w.total()};
}

// blobs[1] (`count` values) or zeros. ONNX's importer gives the bias as a second blob without
// "bias_term"; Caffe's importer says it.
inline std::vector<float> bias_of(const cv::dnn::LayerParams& params, int count) {
  if (params.blobs.size() < 2 || !params.get<bool>("bias_term", true))
    return std::vector<float>(static_cast<std::size_t>(count), 0.0f);
  const cv::Mat b = params.blobs[1].isContinuous() ? params.blobs[1] : params.blobs[1].clone();
  CV_Assert(b.total() == static_cast<std::size_t>(count) && b.depth() == CV_32F);
  return {b.ptr<float>(), b.ptr<float>() + b.total()};
}

// The first input and first output of a forward pass: float, continuous (as OpenCV allocates).
struct LayerBlobs {
  cv::Mat in, out;
};
inline LayerBlobs blobs_of(cv::InputArrayOfArrays inputs_arr, cv::OutputArrayOfArrays outputs_arr) {
  std::vector<cv::Mat> inputs, outputs;
  inputs_arr.getMatVector(inputs);
  outputs_arr.getMatVector(outputs);
  CV_Assert(!inputs.empty() && !outputs.empty());
  LayerBlobs b{inputs[0], outputs[0]};
  CV_Assert(b.in.depth() == CV_32F && b.in.isContinuous() && b.out.isContinuous());
  return b;
}

}  // namespace lrd::segmentation
