// Synthetic benchmark generation speed: render time per frame (single thread) split into its
// stages, PNG encoding, and the whole `write_sequence` throughput on all cores.
// Bar: a 900-frame sequence in under a minute on 2 cores.
// Usage: bench_synth [PRESET] [FRAMES] [clean|tum]
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "bench/yardstick.h"
#include "lrd/synth/sequence_writer.h"
#include "lrd/synth/synthetic_sequence.h"

namespace {
double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

int run(int argc, char** argv) {
  const std::string preset = argc > 1 ? argv[1] : "walking_xyz";
  if (preset == "-h" || preset == "--help") {
    std::printf("Usage: bench_synth [PRESET] [FRAMES] [clean|tum]  (default: walking_xyz 900 clean)\n");
    return 0;
  }
  const int frames = argc > 2 ? std::atoi(argv[2]) : 900;
  if (frames <= 0) {
    std::fprintf(stderr, "bench_synth: FRAMES must be a positive number, not '%s'\n", argv[2]);
    return 1;
  }
  // A third argument: the realism profile (clean, tum).
  const std::string realism = argc > 3 ? argv[3] : "clean";
  if (realism != "clean" && realism != "tum") {
    std::fprintf(stderr, "bench_synth: unknown realism profile '%s' (valid: clean, tum)\n", realism.c_str());
    return 1;
  }
  lrd::synth::SynthOptions opt;
  opt.preset = preset;
  opt.frames = frames;
  opt.realism = lrd::synth::realism_profile(realism);
  fmt::print("realism profile: {}\n", realism);
  const lrd::synth::SyntheticSequence seq(opt);

  // Y timed frame by frame right after each frame's rendering and encoding (interleaved Y,
  // bench/results/performance.md: the yardstick shares the machine's state with the work it
  // divides).
  auto orb = cv::ORB::create(1000, 1.2f, 8);
  std::vector<double> render_ms, encode_ms, y_ms;
  for (int i = 0; i < std::min(frames, 30); ++i) {
    const double t0 = now();
    const auto f = seq.render(i * std::max(1, frames / 30));
    const double t1 = now();
    std::vector<uchar> buf;
    for (const cv::Mat* m : {&f.rgb, &f.depth, &f.mask, &f.static_rgb, &f.static_depth})
      cv::imencode(".png", *m, buf);
    const double t2 = now();
    render_ms.push_back(1e3 * (t1 - t0));
    encode_ms.push_back(1e3 * (t2 - t1));
    cv::Mat grey, descriptors;
    std::vector<cv::KeyPoint> keypoints;
    cv::cvtColor(f.rgb, grey, cv::COLOR_BGR2GRAY);
    const double y0 = now();
    orb->detectAndCompute(grey, cv::noArray(), keypoints, descriptors);
    y_ms.push_back(1e3 * (now() - y0));
  }
  const double y = lrd::bench::median_of(y_ms);
  const double render = lrd::bench::median_of(render_ms), encode = lrd::bench::median_of(encode_ms);
  fmt::print(
      "Y (median OpenCV ORB 1000/1.2/8 detectAndCompute, timed on each frame after rendering it): {:.1f} "
      "ms\n",
      y);
  fmt::print(
      "{}: single thread, median per frame: render {:.1f} ms ({:.2f} Y), PNG encode of 5 images {:.1f} ms "
      "({:.2f} Y)\n",
      preset, render, render / y, encode, encode / y);

  const auto out = std::filesystem::temp_directory_path() / fmt::format("lrd_bench_synth_{}", preset);
  std::filesystem::remove_all(out);
  const auto s = lrd::synth::write_sequence(seq, out);
  std::filesystem::remove_all(out);
  // Bars: clean under a minute, the tum realism profile under three.
  fmt::print("{}: {} frames written in {:.1f} s ({:.1f} frames/s, {:.2f} s per 900 frames; bar: < {} s)\n",
             preset, s.frames, s.seconds, s.frames / s.seconds, 900.0 * s.seconds / s.frames,
             realism == "tum" ? 180 : 60);
  return 0;
}

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {  // an unknown preset, an unwritable temporary folder
    std::fprintf(stderr, "bench_synth: %s\n", e.what());
    return 1;
  }
}
