#include "lrd/segmentation/segmentation_params.h"

#include <algorithm>

#include "lrd/segmentation/onnx_presets.h"
#include "lrd/util/error.h"

namespace lrd::segmentation {

namespace fs = std::filesystem;

const std::vector<std::string>& voc_classes() {
  static const std::vector<std::string> names{
      "background", "aeroplane", "bicycle",     "bird",  "boat",        "bottle", "bus",
      "car",        "cat",       "chair",       "cow",   "diningtable", "dog",    "horse",
      "motorbike",  "person",    "pottedplant", "sheep", "sofa",        "train",  "tvmonitor"};
  return names;
}

const std::vector<std::string>& voc_dynamic_classes() {
  static const std::vector<std::string> names{"person", "bird", "cat", "cow", "dog", "horse", "sheep"};
  return names;
}

std::string to_string(Backend b) {
  switch (b) {
    case Backend::None:
      return "none";
    case Backend::Onnx:
      return "onnx";
    case Backend::Masks:
      return "masks";
  }
  return "?";
}

std::string to_string(Schedule s) {
  return s == Schedule::Sync ? "sync" : "async";
}

namespace {
fs::path resolve(const fs::path& p, const fs::path& base_dir) {
  if (p.empty() || p.is_absolute() || base_dir.empty()) return p;
  std::error_code ec;
  if (fs::exists(base_dir / p, ec)) return base_dir / p;
  return p;
}

template <class Enum>
Enum parse_choice(config::NodeReader& r, const std::string& key, const std::string& fallback,
                  const std::vector<std::pair<std::string, Enum>>& choices) {
  const auto value = r.get<std::string>(key, fallback);
  std::string names;
  for (const auto& [name, e] : choices) {
    if (name == value) return e;
    names += (names.empty() ? "" : ", ") + name;
  }
  r.check(false, key, "must be one of " + names + " (got '" + value + "')");
  return choices.front().second;
}
}  // namespace

SegmentationParams SegmentationParams::from_config(config::NodeReader r, const fs::path& base_dir) {
  SegmentationParams p;
  // A named onnx configuration (onnx_presets.h) supplies the backend and the onnx section's
  // defaults; keys given in the onnx section still override it.
  const auto preset = r.get<std::string>("preset", "");
  r.check(preset.empty() || is_onnx_preset(preset), "preset",
          "names no onnx preset (fnet, selfie, selfie-landscape, espnetv2-voc; got '" + preset + "')");
  p.backend =
      parse_choice<Backend>(r, "backend", preset.empty() ? "none" : "onnx",
                            {{"none", Backend::None}, {"onnx", Backend::Onnx}, {"masks", Backend::Masks}});
  p.schedule =
      parse_choice<Schedule>(r, "schedule", "async", {{"async", Schedule::Async}, {"sync", Schedule::Sync}});
  p.max_wait_ms = r.get("max_wait_ms", p.max_wait_ms);
  r.check(p.max_wait_ms >= 0, "max_wait_ms", "must be >= 0");
  p.stride = r.get("stride", p.stride);
  r.check(p.stride >= 1 && p.stride <= 30, "stride", "must be in [1, 30]");
  p.dilation_px = r.get("dilation_px", p.dilation_px);
  r.check(p.dilation_px >= 0 && p.dilation_px <= 100, "dilation_px", "must be in [0, 100]");
  p.age_dilation_px = r.get("age_dilation_px", p.age_dilation_px);
  r.check(p.age_dilation_px >= 0, "age_dilation_px", "must be >= 0");
  p.max_age_dilation_px = r.get("max_age_dilation_px", p.max_age_dilation_px);
  r.check(p.max_age_dilation_px >= 0 && p.max_age_dilation_px <= 100, "max_age_dilation_px",
          "must be in [0, 100]");

  {
    config::NodeReader o = r.section("onnx");
    OnnxParams& q = p.onnx;
    const fs::path model = resolve(o.get<fs::path>("model", fs::path{}), base_dir);
    // The preset matters only to the onnx backend (its model may not even be there otherwise).
    const bool use_preset = !preset.empty() && p.backend == Backend::Onnx;
    try {
      q = onnx_preset(use_preset ? preset : "fnet", model);
    } catch (const Error& e) {
      r.check(false, "preset", e.what());
    }
    q.input_width = o.get("input_width", q.input_width);
    q.input_height = o.get("input_height", q.input_height);
    o.check(q.input_width >= 8 && q.input_width <= 4096, "input_width", "must be in [8, 4096]");
    o.check(q.input_height >= 8 && q.input_height <= 4096, "input_height", "must be in [8, 4096]");
    q.scale = o.get("scale", q.scale);
    q.mean = o.get("mean", q.mean);
    o.check(q.mean.size() == 3, "mean", "must have 3 values");
    q.std = o.get("std", q.std);
    o.check(q.std.size() == 3 && std::all_of(q.std.begin(), q.std.end(), [](double s) { return s > 0; }),
            "std", "must have 3 positive values");
    const auto order = o.get<std::string>("input_order", q.input_rgb ? "rgb" : "bgr");
    o.check(order == "rgb" || order == "bgr", "input_order", "must be rgb or bgr");
    q.input_rgb = order == "rgb";
    const char* layouts[] = {"logits", "probability", "labels"};
    q.output = parse_choice<OutputLayout>(o, "output", layouts[static_cast<int>(q.output)],
                                          {{"logits", OutputLayout::Logits},
                                           {"probability", OutputLayout::Probability},
                                           {"labels", OutputLayout::Labels}});
    q.classes = o.get("classes", q.classes);
    q.dynamic_classes = o.get("dynamic_classes", q.dynamic_classes);
    q.dynamic_ids.clear();
    q.threshold = o.get("threshold", q.threshold);
    q.upsample_logits = o.get("upsample_logits", q.upsample_logits);
    q.own_kernels = o.get("own_kernels", q.own_kernels);
    o.check(q.threshold > 0 && q.threshold < 1, "threshold", "must be in (0, 1)");
    if (q.output == OutputLayout::Probability) {
      q.dynamic_ids = {0};
    } else {
      for (const std::string& name : q.dynamic_classes) {
        const auto it = std::find(q.classes.begin(), q.classes.end(), name);
        o.check(it != q.classes.end(), "dynamic_classes",
                "names '" + name + "', which is not among the classes");
        q.dynamic_ids.push_back(static_cast<int>(it - q.classes.begin()));
      }
    }
    o.finish();
  }
  {
    config::NodeReader m = r.section("masks");
    p.masks.folder = resolve(m.get<fs::path>("folder", fs::path{}), base_dir);
    p.masks.dynamic_values = m.get("dynamic_values", p.masks.dynamic_values);
    m.check(std::all_of(p.masks.dynamic_values.begin(), p.masks.dynamic_values.end(),
                        [](int v) { return v >= 0 && v <= 255; }),
            "dynamic_values", "must be pixel values in [0, 255]");
    p.masks.max_time_difference = m.get("max_time_difference", p.masks.max_time_difference);
    m.check(p.masks.max_time_difference >= 0, "max_time_difference", "must be >= 0");
    m.finish();
  }
  r.finish();
  return p;
}

}  // namespace lrd::segmentation
