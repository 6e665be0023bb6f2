#include "lrd/segmentation/onnx_presets.h"

#include <algorithm>
#include <cstdlib>

#include "lrd/util/error.h"
#include "lrd/util/project_files.h"

namespace lrd::segmentation {

namespace fs = std::filesystem;

const std::vector<std::string>& onnx_preset_names() {
  static const std::vector<std::string> names{"fnet", "selfie", "selfie-landscape", "espnetv2-voc"};
  return names;
}

bool is_onnx_preset(const std::string& name) {
  const auto& n = onnx_preset_names();
  return std::find(n.begin(), n.end(), name) != n.end();
}

namespace {

// RGB in [0, 1], no mean/std, 1x1xHxW person probability (already through the sigmoid).
OnnxParams selfie(int width, int height, const fs::path& file) {
  OnnxParams p;
  p.model = file;
  p.input_width = width;
  p.input_height = height;
  p.scale = 1.0 / 255.0;
  p.mean = {0.0, 0.0, 0.0};
  p.std = {1.0, 1.0, 1.0};
  p.input_rgb = true;
  p.output = OutputLayout::Probability;
  p.classes = {"person"};
  p.dynamic_classes = {"person"};
  p.dynamic_ids = {0};
  p.threshold = 0.5;
  return p;
}

OnnxParams voc(int width, int height, const fs::path& file) {
  OnnxParams p;
  p.model = file;
  p.input_width = width;
  p.input_height = height;
  p.output = OutputLayout::Logits;
  p.classes = voc_classes();
  p.dynamic_classes = voc_dynamic_classes();
  for (const std::string& name : p.dynamic_classes)
    p.dynamic_ids.push_back(
        static_cast<int>(std::find(p.classes.begin(), p.classes.end(), name) - p.classes.begin()));
  return p;
}

}  // namespace

OnnxParams onnx_preset(const std::string& name, const fs::path& model) {
  const auto pick = [&](const char* shipped) {
    return model.empty() ? util::find_project_file(shipped) : model;
  };
  if (name == "fnet") {  // RGB / 255, no mean/std; logits at half the input size (training/fnet/model.py)
    OnnxParams p = voc(160, 120, pick("models/fnet-lite.onnx"));
    p.upsample_logits = true;
    return p;
  }
  if (name == "selfie" || name == "selfie-landscape") {
    const bool landscape = name == "selfie-landscape";
    const fs::path file = pick(landscape ? "data/models/selfie_segmentation_landscape.onnx"
                                         : "data/models/selfie_segmentation.onnx");
    std::error_code ec;
    if (model.empty() && !fs::is_regular_file(file, ec))
      throw file_error(file,
                       "the converted MediaPipe selfie model is not there: run scripts/fetch-models.sh "
                       "(fetches the npm package and converts it to ONNX)");
    return landscape ? selfie(256, 144, file) : selfie(256, 256, file);
  }
  if (name == "espnetv2-voc") {
    if (model.empty())
      throw Error(
          "segmenter espnetv2-voc needs its model file (ESPNetv2 on VOC, 384x288 input): "
          "give its path (lrdslam run --segmenter-model, lrdslam segment --model-file, or "
          "segmentation.onnx.model)");
    OnnxParams p = voc(384, 288, model);
    p.mean = {0.485, 0.456, 0.406};  // ImageNet statistics, RGB
    p.std = {0.229, 0.224, 0.225};
    return p;
  }
  std::string names;
  for (const std::string& n : onnx_preset_names()) names += (names.empty() ? "" : ", ") + n;
  throw Error("unknown segmentation preset '" + name + "' (onnx presets: " + names + ")");
}

}  // namespace lrd::segmentation
