#pragma once
// The `segmentation` section of the config: which backend, how tracking waits for it, and each
// backend's own settings (config/default.yaml documents every key).
#include <filesystem>
#include <string>
#include <vector>

#include "lrd/config/node_reader.h"

namespace lrd::segmentation {

enum class Backend { None, Onnx, Masks };
enum class Schedule {
  Sync,   // the paper's: frame t is tracked with the mask of frame t
  Async,  // real time: the newest mask within a bounded wait, carried to frame t
};
enum class OutputLayout {
  Logits,       // N x C x H x W class scores; label = argmax over C
  Probability,  // N x 1 x H x W probability of "dynamic"
  Labels,       // N x 1 x H x W (or N x H x W) class indices
};

struct OnnxParams {
  std::filesystem::path model;  // resolved: absolute, or relative to the working directory
  int input_width = 160;        // the network's input size (fnet-lite's)
  int input_height = 120;
  double scale = 1.0 / 255.0;               // pixel value x scale, then (x - mean) / std per channel
  std::vector<double> mean{0.0, 0.0, 0.0};  // in the network's channel order
  std::vector<double> std{1.0, 1.0, 1.0};
  bool input_rgb = true;  // the network wants RGB (false: BGR)
  OutputLayout output = OutputLayout::Logits;
  std::vector<std::string> classes;          // index -> name
  std::vector<std::string> dynamic_classes;  // names counted as dynamic
  double threshold = 0.5;                    // probability layout: dynamic above it
  // logits layout: logits coarser than the input are resized bilinearly to the input size before
  // the arg-max (how FNet-lite is trained); false: arg-max first, then nearest-neighbour.
  bool upsample_logits = false;
  // Our kernels where OpenCV 4.6 DNN is slow (own_kernels.h: non-3x3 depthwise and RGB-input
  // convolutions, kernel == stride transposed convolutions, sigmoid, linear resize, global average
  // pooling); false: OpenCV's layers only. The output is the same to float rounding.
  bool own_kernels = true;
  // Indices of dynamic_classes in classes (filled by from_config).
  std::vector<int> dynamic_ids;
};

struct MaskFolderParams {
  std::filesystem::path folder;        // one PNG per frame, named by its timestamp (TUM rgb names)
  std::vector<int> dynamic_values;     // pixel values counted as dynamic; empty: any nonzero
  double max_time_difference = 0.002;  // seconds between the frame and the mask's name
};

struct SegmentationParams {
  Backend backend = Backend::None;
  Schedule schedule = Schedule::Async;
  // async: longest wait for the current frame's mask. 0 (measured best on 2 cores): never wait,
  // take the previous frame's mask carried over; the network runs beside the next frame's tracking.
  double max_wait_ms = 0.0;
  // async: the network gets every stride-th frame, the others take its mask carried over. 2
  // (measured on 2 cores): half the network's CPU, same ATE, the frames between run without it.
  int stride = 2;
  int dilation_px = 7;  // masks grow by this radius (people's outlines, blur)
  // async: extra dilation per frame of mask age (motion the propagation cannot predict), capped.
  double age_dilation_px = 4.0;
  int max_age_dilation_px = 24;
  OnnxParams onnx;
  MaskFolderParams masks;

  // Reads the `segmentation` section; relative paths resolve against `base_dir` (the config
  // file's folder) when the file exists there, else against the working directory.
  static SegmentationParams from_config(config::NodeReader reader,
                                        const std::filesystem::path& base_dir = {});
};

// The 21 Pascal VOC classes (0 = background, 15 = person).
[[nodiscard]] const std::vector<std::string>& voc_classes();
// The paper's movable classes: person, bird, cat, cow, dog, horse, sheep.
[[nodiscard]] const std::vector<std::string>& voc_dynamic_classes();

[[nodiscard]] std::string to_string(Backend b);
[[nodiscard]] std::string to_string(Schedule s);

}  // namespace lrd::segmentation
