#pragma once
// Named configurations of the `onnx` backend (--segmenter NAME, or `segmentation.preset`):
//   fnet              our FNet-lite (models/fnet-lite.onnx), 21 VOC classes, trained on the
//                     synthetic benchmark — the model for synthetic sequences
//   selfie            MediaPipe selfie segmentation 256x256, person probability > 0.5
//   selfie-landscape  the same network at 256x144 (faster) — the default for real data
//   espnetv2-voc      ESPNetv2 on Pascal VOC at 384x288 (model file supplied by the user)
// The selfie models are converted from MediaPipe's TFLite files by tools/tflite2onnx
// (scripts/fetch-models.sh) into data/models/.
#include <filesystem>
#include <string>
#include <vector>

#include "lrd/segmentation/segmentation_params.h"

namespace lrd::segmentation {

[[nodiscard]] const std::vector<std::string>& onnx_preset_names();
[[nodiscard]] bool is_onnx_preset(const std::string& name);

// The preset's pre/post-processing and model. `model` overrides the preset's file (required for
// espnetv2-voc). Throws lrd::Error for an unknown name, when espnetv2-voc has no model, and when
// a selfie model has not been converted yet (saying how); OnnxSegmenter checks the file itself.
[[nodiscard]] OnnxParams onnx_preset(const std::string& name, const std::filesystem::path& model = {});

}  // namespace lrd::segmentation
