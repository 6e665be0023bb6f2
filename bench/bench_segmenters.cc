// Time per frame of each segmentation preset (bench/results/segmenters.md) through the same
// OnnxSegmenter the SLAM thread uses (pre-processing, network, post-processing at 640x480), and of
// the network alone, against the yardstick Y timed frame by frame between each preset's runs on the
// same frames. Targets as ratios: "<= 15 ms" (fnet-lite) is 0.4 Y, "<= 30 ms" (selfie-landscape) is
// 0.75 Y.
// Usage: bench_segmenters [--frames N] [--espnet FILE.onnx] [--photos DIR] [--out FILE.md]
//   Presets whose model is absent are listed as such (selfie: scripts/fetch-models.sh).
//   --photos: real photographs (default ../shared/data/people, or $LRD_SHARED_DIR/data/people): a
//   second table times each preset on them against Y on the same photographs, the yardstick of
//   the real sequences the selfie presets are for (ORB costs more on real texture than on renders).
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/dnn.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bench/yardstick.h"
#include "lrd/segmentation/onnx_presets.h"
#include "lrd/segmentation/onnx_segmenter.h"
#include "lrd/segmentation/own_kernels.h"
#include "lrd/synth/synthetic_sequence.h"
#include "lrd/util/error.h"
#include "lrd/util/project_files.h"

namespace {

struct Row {
  std::string preset, input, note;
  double ms = 0.0;                 // the whole OnnxSegmenter::segment call
  double network_ms = 0.0;         // the network alone: setInput + forward on a ready blob
  double opencv_network_ms = 0.0;  // the same with OpenCV's layers only (no own kernels)
  double y_ms = 0.0;               // the yardstick, timed frame by frame between this preset's runs
  double photo_ms = 0.0;           // the whole call on real photographs (when there are any)
  double photo_y_ms = 0.0;         // the yardstick on those photographs, timed between them
  std::optional<double> target_y;
};

}  // namespace

int main(int argc, char** argv) {
  int frames = 30;
  std::string espnet, out, photos_dir;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--frames")
      frames = std::max(3, std::atoi(argv[i + 1]));
    else if (a == "--espnet")
      espnet = argv[i + 1];
    else if (a == "--out")
      out = argv[i + 1];
    else if (a == "--photos")
      photos_dir = argv[i + 1];
    else {
      std::fprintf(
          stderr,
          "usage: bench_segmenters [--frames N] [--espnet FILE.onnx] [--photos DIR] [--out FILE.md]\n");
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
  std::vector<cv::Mat> photos, photo_grey;
  if (photos_dir.empty()) {
    const char* env = std::getenv("LRD_SHARED_DIR");
    photos_dir = (env != nullptr && *env != '\0')
                     ? (std::filesystem::path(env) / "data" / "people").string()
                     : lrd::util::find_project_file("../shared/data/people").string();
  }
  std::error_code ec;
  if (std::filesystem::is_directory(photos_dir, ec)) {
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(photos_dir, ec))
      if (e.is_regular_file()) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      cv::Mat img = cv::imread(f.string(), cv::IMREAD_COLOR);
      if (img.empty()) continue;
      cv::resize(img, img, cv::Size(640, 480), 0, 0, cv::INTER_AREA);  // a camera frame's size
      cv::Mat g;
      cv::cvtColor(img, g, cv::COLOR_BGR2GRAY);
      photos.push_back(img);
      photo_grey.push_back(g);
    }
  }
  // Y is timed interleaved with each preset's runs, frame by frame: these machines drift by tens of
  // per cent between minutes, and a ratio only means something when both sides saw the same load.
  auto orb = cv::ORB::create(1000, 1.2f, 8);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  orb->detectAndCompute(grey[0], cv::noArray(), keypoints, descriptors);  // warm-up
  std::vector<double> all_y;

  std::vector<Row> rows;
  for (const std::string& name : lrd::segmentation::onnx_preset_names()) {
    Row r;
    r.preset = name;
    if (name == "fnet") r.target_y = 0.4;
    if (name == "selfie-landscape") r.target_y = 0.75;
    try {
      if (name == "espnetv2-voc" && espnet.empty()) throw lrd::Error("no model given (--espnet FILE)");
      const auto params =
          lrd::segmentation::onnx_preset(name, name == "espnetv2-voc" ? espnet : std::string{});
      lrd::segmentation::OnnxSegmenter seg(params);
      r.input = fmt::format("{}x{}", params.input_width, params.input_height);
      // The network alone, as fnet-lite's target "ms per frame in OpenCV DNN" reads: a second copy
      // of the model, fed a ready blob (pixel values do not change its time); with our kernels as
      // the segmenter has them (segmentation.onnx.own_kernels), and a third copy with OpenCV's
      // only.
      const cv::Size in(params.input_width, params.input_height);
      const cv::Mat blob =
          cv::dnn::blobFromImage(bgr[0], params.scale, in, cv::Scalar(), true, false, CV_32F);
      const auto read_net = [&](bool own) {
        std::optional<lrd::segmentation::OwnKernelsScope> scope;
        if (own) scope.emplace();
        cv::dnn::Net n = cv::dnn::readNetFromONNX(params.model.string());
        n.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
        n.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
        n.setInput(blob);
        (void)n.forward();  // warm-up (and the layers OpenCV creates only now) inside the scope
        return n;
      };
      cv::dnn::Net net = read_net(params.own_kernels), opencv_net = read_net(false);
      const auto run_network = [&] {
        net.setInput(blob);
        (void)net.forward();
      };
      const auto run_opencv_network = [&] {
        opencv_net.setInput(blob);
        (void)opencv_net.forward();
      };
      (void)seg.segment(bgr[0], false, 0.0);  // warm-up: first-run allocations
      std::vector<double> ms, network_ms, opencv_ms, y_ms;
      const auto ms_of = [](auto&& fn) {
        const auto t0 = std::chrono::steady_clock::now();
        fn();
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      };
      for (std::size_t i = 0; i < bgr.size(); ++i) {
        y_ms.push_back(ms_of([&] { orb->detectAndCompute(grey[i], cv::noArray(), keypoints, descriptors); }));
        ms.push_back(ms_of([&] { (void)seg.segment(bgr[i], false, 0.0); }));
        network_ms.push_back(ms_of(run_network));
        opencv_ms.push_back(ms_of(run_opencv_network));
      }
      r.ms = lrd::bench::median_of(ms);
      r.network_ms = lrd::bench::median_of(network_ms);
      r.opencv_network_ms = lrd::bench::median_of(opencv_ms);
      r.y_ms = lrd::bench::median_of(y_ms);
      all_y.insert(all_y.end(), y_ms.begin(), y_ms.end());
      if (!photos.empty()) {
        std::vector<double> photo_ms, photo_y;
        for (int i = 0; i < frames; ++i) {
          const std::size_t k = static_cast<std::size_t>(i) % photos.size();
          photo_y.push_back(
              ms_of([&] { orb->detectAndCompute(photo_grey[k], cv::noArray(), keypoints, descriptors); }));
          photo_ms.push_back(ms_of([&] { (void)seg.segment(photos[k], false, 0.0); }));
        }
        r.photo_ms = lrd::bench::median_of(photo_ms);
        r.photo_y_ms = lrd::bench::median_of(photo_y);
      }
    } catch (const std::exception& e) {
      r.note = e.what();
    }
    rows.push_back(r);
  }
  const double y = lrd::bench::median_of(all_y);

  std::string md = fmt::format(
      "# Segmentation presets: time per 640x480 frame (OpenCV DNN, CPU)\n\n"
      "{} frames of synthetic walking_xyz; medians of the network alone (OpenCV DNN `forward` on a "
      "ready blob) and of the whole `OnnxSegmenter::segment` call (resize, normalisation, network, "
      "post-processing to a full-size mask); the network with our kernels where OpenCV 4.6 is slow "
      "(`segmentation.onnx.own_kernels`, the default) and with OpenCV's layers only. Y = {:.2f} ms "
      "overall: median `cv::ORB` detectAndCompute on "
      "the same frames, timed frame by frame between each preset's runs; each row's ratios use the Y "
      "timed beside it (column Y). Targets are judged on the network alone for `fnet` (its target: "
      "\"ms per frame in OpenCV DNN\") and on the whole call for `selfie-landscape` (its target: \"time "
      "per frame of each preset\").\n\n"
      "| preset | input | Y ms | network ms | × Y | OpenCV layers only ms | × Y | whole call ms | × Y | "
      "target |\n"
      "|---|---|---:|---:|---:|---:|---:|---:|---:|---|\n",
      bgr.size(), y);
  for (const Row& r : rows) {
    if (!r.note.empty()) {
      md += fmt::format("| {} | | — | — | — | — | — | — | — | not run: {} |\n", r.preset, r.note);
      continue;
    }
    const double judged = (r.preset == "fnet" ? r.network_ms : r.ms) / r.y_ms;
    const std::string target = r.target_y ? fmt::format("≤ {:.2f} Y ({}): {}", *r.target_y,
                                                        r.preset == "fnet" ? "network" : "whole call",
                                                        judged <= *r.target_y ? "met" : "NOT met")
                                          : "";
    md += fmt::format("| {} | {} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {} |\n",
                      r.preset, r.input, r.y_ms, r.network_ms, r.network_ms / r.y_ms, r.opencv_network_ms,
                      r.opencv_network_ms / r.y_ms, r.ms, r.ms / r.y_ms, target);
  }
  if (!photos.empty()) {
    md += fmt::format(
        "\nOn {} real photographs ({}, resized to 640x480, cycled over {} runs): the whole call against "
        "Y timed on the same photographs.\n\n"
        "| preset | Y ms (photos) | whole call ms | × Y | target |\n|---|---:|---:|---:|---|\n",
        photos.size(), photos_dir, frames);
    for (const Row& r : rows) {
      if (!r.note.empty() || r.photo_ms <= 0.0) continue;
      const double ratio = r.photo_ms / r.photo_y_ms;
      const std::string target =
          r.target_y && r.preset != "fnet"
              ? fmt::format("≤ {:.2f} Y: {}", *r.target_y, ratio <= *r.target_y ? "met" : "NOT met")
              : "";
      md += fmt::format("| {} | {:.2f} | {:.2f} | {:.2f} | {} |\n", r.preset, r.photo_y_ms, r.photo_ms, ratio,
                        target);
    }
  } else {
    md += fmt::format("\nNo real photographs at {} (--photos DIR): the real-photograph table is left out.\n",
                      photos_dir);
  }
  std::fputs(md.c_str(), stdout);
  if (!out.empty()) std::ofstream(out) << md;
  return 0;
}
