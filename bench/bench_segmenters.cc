// Time per frame of each segmentation preset (issue 8), through the same OnnxSegmenter the SLAM
// thread uses (pre-processing, network, post-processing at 640x480), against the yardstick Y
// measured on the same frames. Targets as ratios: "<= 15 ms" (fnet-lite) is 0.4 Y, "<= 30 ms"
// (selfie-landscape) is 0.75 Y.
// Usage: bench_segmenters [--frames N] [--espnet FILE.onnx] [--out FILE.md]
//   Presets whose model is absent are listed as such (selfie: scripts/fetch-models.sh).
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bench/yardstick.h"
#include "lrd/segmentation/onnx_presets.h"
#include "lrd/segmentation/onnx_segmenter.h"
#include "lrd/synth/synthetic_sequence.h"
#include "lrd/util/error.h"

namespace {

struct Row {
  std::string preset, input, note;
  double ms = 0.0;
  std::optional<double> target_y;
};

}  // namespace

int main(int argc, char** argv) {
  int frames = 30;
  std::string espnet, out;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--frames") frames = std::max(3, std::atoi(argv[i + 1]));
    else if (a == "--espnet") espnet = argv[i + 1];
    else if (a == "--out") out = argv[i + 1];
    else {
      std::fprintf(stderr, "usage: bench_segmenters [--frames N] [--espnet FILE.onnx] [--out FILE.md]\n");
      return 2;
    }
  }
  // Frames of synthetic walking_xyz (people in view), rendered in memory.
  lrd::synth::SynthOptions so;
  so.preset = "walking_xyz";
  const lrd::synth::SyntheticSequence seq(so);
  std::vector<cv::Mat> bgr, grey;
  const int step = std::max(1, seq.size() / frames);
  for (int i = 0; i < frames; ++i) {
    bgr.push_back(seq.render(i * step).rgb);  // the renderer's colour images are BGR, like imread
    cv::Mat g;
    cv::cvtColor(bgr.back(), g, cv::COLOR_BGR2GRAY);
    grey.push_back(g);
  }
  const double y_before = lrd::bench::yardstick_ms(grey);

  std::vector<Row> rows;
  for (const std::string& name : lrd::segmentation::onnx_preset_names()) {
    Row r;
    r.preset = name;
    if (name == "fnet") r.target_y = 0.4;
    if (name == "selfie-landscape") r.target_y = 0.75;
    try {
      if (name == "espnetv2-voc" && espnet.empty()) throw lrd::Error("no model given (--espnet FILE)");
      const auto params = lrd::segmentation::onnx_preset(name, name == "espnetv2-voc" ? espnet : std::string{});
      lrd::segmentation::OnnxSegmenter seg(params);
      r.input = fmt::format("{}x{}", params.input_width, params.input_height);
      (void)seg.segment(bgr[0], false, 0.0);  // warm-up: first-run allocations
      std::vector<double> ms;
      for (const cv::Mat& f : bgr) {
        const auto t0 = std::chrono::steady_clock::now();
        (void)seg.segment(f, false, 0.0);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      }
      r.ms = lrd::bench::median_of(ms);
    } catch (const std::exception& e) {
      r.note = e.what();
    }
    rows.push_back(r);
  }
  const double y = 0.5 * (y_before + lrd::bench::yardstick_ms(grey));

  std::string md = fmt::format(
      "# Segmentation presets: time per 640x480 frame (OpenCV DNN, CPU)\n\n"
      "{} frames of synthetic walking_xyz; median of the whole `OnnxSegmenter::segment` call (resize, "
      "normalisation, network, post-processing to a full-size mask). Y = {:.2f} ms (median `cv::ORB` "
      "detectAndCompute on the same frames, before and after).\n\n"
      "| preset | input | ms | × Y | target |\n|---|---|---:|---:|---|\n",
      bgr.size(), y);
  for (const Row& r : rows) {
    if (!r.note.empty()) {
      md += fmt::format("| {} | | — | — | not run: {} |\n", r.preset, r.note);
      continue;
    }
    const double ratio = r.ms / y;
    const std::string target = r.target_y ? fmt::format("≤ {:.2f} Y: {}", *r.target_y,
                                                         ratio <= *r.target_y ? "met" : "NOT met")
                                          : "";
    md += fmt::format("| {} | {} | {:.1f} | {:.2f} | {} |\n", r.preset, r.input, r.ms, ratio, target);
  }
  std::fputs(md.c_str(), stdout);
  if (!out.empty()) std::ofstream(out) << md;
  return 0;
}
