#pragma once
// Our kernels for the layers OpenCV 4.6 DNN runs slowly, used by OnnxSegmenter (config
// `segmentation.onnx.own_kernels`, on by default). The model file stays plain ONNX that any OpenCV
// reads; the output is OpenCV's to float rounding (tests/unit/test_own_kernels.cc).
//
// OpenCV creates a network's layers while it reads the file, through its layer factory: we add our
// own constructors for "Convolution", "Deconvolution", "Sigmoid", "HardSwish", "Resize", "Pooling"
// and "Padding" to it once per process; they build our layer (GroupedConvolutionLayer,
// TransposedConvolutionLayer, SigmoidLayer, HardSwishLayer, LinearResizeLayer,
// GlobalAveragePoolingLayer, ZeroPaddingLayer) where we have a kernel for it while an
// OwnKernelsScope is alive on the calling thread, and OpenCV's own layer otherwise (other threads,
// other networks, other layers).

namespace lrd::segmentation {

class OwnKernelsScope {
 public:
  OwnKernelsScope();
  ~OwnKernelsScope();
  OwnKernelsScope(const OwnKernelsScope&) = delete;
  OwnKernelsScope& operator=(const OwnKernelsScope&) = delete;

 private:
  bool previous_;
};

}  // namespace lrd::segmentation
