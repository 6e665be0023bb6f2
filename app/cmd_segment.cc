// `lrdslam segment`: run a segmentation preset on one's own images and write, per image, the
// dynamic mask, an overlay and (for class-label models) the label map — to check a model on the
// kind of scene it will see before trusting it inside SLAM.
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "app/commands.h"
#include "lrd/io/image_file.h"
#include "lrd/segmentation/onnx_presets.h"
#include "lrd/segmentation/onnx_segmenter.h"
#include "lrd/util/error.h"

namespace lrd::app {
namespace {

namespace fs = std::filesystem;

struct SegmentCli {
  std::string model = "selfie-landscape", model_file, out;
  std::vector<std::string> images;
};

// Dynamic pixels tinted red, other non-background classes blue, the rest as photographed.
cv::Mat overlay(const cv::Mat& bgr, const cv::Mat& labels, const cv::Mat& mask) {
  cv::Mat tint = bgr.clone();
  tint.setTo(cv::Scalar(255, 96, 0), (labels != 0) & (mask == 0));
  tint.setTo(cv::Scalar(0, 0, 255), mask);
  cv::Mat out;
  cv::addWeighted(bgr, 0.5, tint, 0.5, 0.0, out);
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  cv::drawContours(out, contours, -1, cv::Scalar(0, 0, 255), std::max(1, bgr.cols / 400));
  return out;
}

void write_png(const fs::path& file, const cv::Mat& img) {
  io::write_image_file(file, img);
}

void segment_images(const SegmentCli& cli) {
  const segmentation::OnnxParams params = segmentation::onnx_preset(cli.model, cli.model_file);
  segmentation::OnnxSegmenter seg(params);
  std::error_code ec;
  fs::create_directories(cli.out, ec);
  if (ec) throw file_error(cli.out, "cannot create the output folder: " + ec.message());
  std::printf("model: %s (%s, input %dx%d)\n", cli.model.c_str(), params.model.string().c_str(),
              params.input_width, params.input_height);
  const bool multi_class = params.output != segmentation::OutputLayout::Probability;
  for (const std::string& name : cli.images) {
    std::error_code missing;
    if (!fs::is_regular_file(name, missing)) throw file_error(name, "no such image file");
    const cv::Mat bgr = cv::imread(name, cv::IMREAD_COLOR);
    if (bgr.empty())
      throw file_error(name, "cannot read this image (missing, or not an image OpenCV decodes)");
    const auto t0 = std::chrono::steady_clock::now();
    const cv::Mat labels = seg.labels(bgr, false);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    // The dynamic mask from the labels (the network ran once).
    cv::Mat mask;
    if (multi_class) {
      mask = cv::Mat::zeros(labels.size(), CV_8UC1);
      for (int id : params.dynamic_ids) mask.setTo(255, labels == id);
    } else {
      mask = labels != 0;  // probability layout: 1 above the threshold
    }
    const std::string stem = fs::path(name).stem().string();
    write_png(fs::path(cli.out) / (stem + "_mask.png"), mask);
    write_png(fs::path(cli.out) / (stem + "_overlay.png"), overlay(bgr, labels, mask));
    if (multi_class) write_png(fs::path(cli.out) / (stem + "_labels.png"), labels);
    std::printf("%s: %dx%d, dynamic %.1f %% of the image, %.1f ms (network and post-processing)\n",
                name.c_str(), bgr.cols, bgr.rows,
                100.0 * cv::countNonZero(mask) / static_cast<double>(mask.total()), ms);
  }
  std::printf("wrote %s/<image>_{mask,overlay%s}.png\n", cli.out.c_str(), multi_class ? ",labels" : "");
}

}  // namespace

void register_segment_command(CLI::App& app) {
  auto cli = std::make_shared<SegmentCli>();
  CLI::App* cmd = app.add_subcommand("segment", "Run a segmentation model on images: masks and overlays");
  cmd->add_option("--model", cli->model,
                  "Preset: selfie-landscape (real people, fast), selfie, espnetv2-voc (needs --model-file), "
                  "fnet (our synthetic-benchmark model)")
      ->capture_default_str();
  cmd->add_option("--model-file", cli->model_file,
                  "The preset's ONNX file, instead of the shipped/cached one");
  cmd->add_option("--out", cli->out, "Output folder")->required();
  cmd->add_option("images", cli->images, "Image files (PNG, JPEG, ...)")->required();
  cmd->callback([cli] { segment_images(*cli); });
}

}  // namespace lrd::app
