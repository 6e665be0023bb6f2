#pragma once
// Base of our element-wise activations: OpenCV 4.6 evaluates some of its own one scalar call at a
// time (sigmoid: 5 ns a value; hard-swish: 1.8 ns, 0.27 ms after selfie-landscape's first layer
// alone, and it follows 11 of its layers). Ours are written so the compiler vectorises them. An
// activation layer like OpenCV's, so that OpenCV fuses it into the layer before it the same way and
// calls forwardSlice on that layer's output. Created through OwnKernelsScope (own_kernels.h).
#include <opencv2/dnn.hpp>
#include <opencv2/dnn/all_layers.hpp>
#include <vector>

namespace lrd::segmentation {

class FastActivationLayer : public cv::dnn::ActivationLayer {
 public:
  bool supportBackend(int backend_id) override;
  bool getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, int required_outputs,
                       std::vector<cv::dnn::MatShape>& outputs,
                       std::vector<cv::dnn::MatShape>& internals) const override;
  void forward(cv::InputArrayOfArrays inputs, cv::OutputArrayOfArrays outputs,
               cv::OutputArrayOfArrays internals) override;
  // `len` values of each channel plane cn0..cn1-1, planes `plane_size` apart (OpenCV's contract).
  void forwardSlice(const float* src, float* dst, int len, size_t plane_size, int cn0,
                    int cn1) const override;

 protected:
  // dst[i] = f(src[i]) for n values; in place allowed.
  virtual void apply(const float* src, float* dst, int n) const = 0;
};

}  // namespace lrd::segmentation
