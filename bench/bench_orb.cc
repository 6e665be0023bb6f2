// ORB extraction speed against the yardstick Y: the median time of OpenCV's
// cv::ORB::create(1000, 1.2f, 8)->detectAndCompute on the same grey frames. Prints Y, our
// extractor's median, ours as a multiple of Y (target: well under 1 Y) and keypoint counts.
// Usage: bench_orb [TUM_SEQUENCE_DIR] [FRAMES]   (default: 30 frames of synthetic walking_xyz)
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "bench/yardstick.h"
#include "lrd/features/orb_extractor.h"
#include "lrd/io/tum_sequence.h"
#include "lrd/synth/synthetic_sequence.h"

namespace {
double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
// Median Hamming distance between descriptors of unrelated keypoints (rows i and i + n/2): near
// 128 when the 256 bits are even and uncorrelated, lower when they are biased.
double spread(const cv::Mat& d) {
  std::vector<double> h;
  for (int i = 0; i + d.rows / 2 < d.rows && d.rows > 1; ++i)
    h.push_back(cv::norm(d.row(i), d.row(i + d.rows / 2), cv::NORM_HAMMING));
  return lrd::bench::median_of(h);
}
cv::Mat grey_of(const cv::Mat& bgr) {
  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  return grey;
}

std::vector<cv::Mat> load_frames(int argc, char** argv, std::string& source) {
  const int frames = argc > 2 ? std::max(1, std::atoi(argv[2])) : 30;
  std::vector<cv::Mat> greys;
  if (argc > 1) {
    const auto seq = lrd::io::TumSequence::open(argv[1]);
    const std::size_t stride = std::max<std::size_t>(1, seq.size() / frames);
    for (std::size_t i = 0; i < seq.size() && greys.size() < static_cast<std::size_t>(frames); i += stride) {
      greys.push_back(grey_of(seq.load_rgbd(i, 5000.0).rgb));
    }
    source = argv[1];
  } else {
    lrd::synth::SynthOptions opt;
    opt.preset = "walking_xyz";
    const lrd::synth::SyntheticSequence seq(opt);
    const int stride = std::max(1, seq.size() / frames);
    for (int i = 0; i < frames; ++i) greys.push_back(grey_of(seq.render(i * stride).rgb));
    source = "synthetic walking_xyz";
  }
  return greys;
}
}  // namespace

int main(int argc, char** argv) {
  std::string source;
  const std::vector<cv::Mat> greys = load_frames(argc, argv, source);
  lrd::features::OrbExtractor ours{lrd::features::OrbParams{}};
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;

  // Y as lrd::bench::yardstick_ms defines it, but timed frame by frame alternately with ours, so
  // that the load of a shared machine weighs on both alike; a first round warms both up.
  auto cv_orb = cv::ORB::create(1000, 1.2f, 8);
  std::vector<double> cv_ms, our_ms, our_count, cv_count, our_spread, cv_spread;
  for (int round = 0; round < 2; ++round) {
    for (const cv::Mat& g : greys) {
      double t0 = now();
      cv_orb->detectAndCompute(g, cv::noArray(), kps, desc);
      const double t_cv = 1e3 * (now() - t0);
      if (round == 1) {
        cv_ms.push_back(t_cv);
        cv_count.push_back(static_cast<double>(kps.size()));
        cv_spread.push_back(spread(desc));
      }
      t0 = now();
      ours.extract(g, cv::Mat(), kps, desc);
      const double t_ours = 1e3 * (now() - t0);
      if (round == 1) {
        our_ms.push_back(t_ours);
        our_count.push_back(static_cast<double>(kps.size()));
        our_spread.push_back(spread(desc));
      }
    }
  }
  const double y = lrd::bench::median_of(cv_ms);
  const double o = lrd::bench::median_of(our_ms);
  fmt::print("{}: {} frames {}x{}\n", source, greys.size(), greys[0].cols, greys[0].rows);
  fmt::print("Y    (cv::ORB 1000/1.2/8 detectAndCompute) median {:6.2f} ms, keypoints median {:.0f}\n", y,
             lrd::bench::median_of(cv_count));
  fmt::print(
      "ours (lrd::features::OrbExtractor)         median {:6.2f} ms, keypoints median {:.0f} (min {:.0f})\n",
      o, lrd::bench::median_of(our_count), *std::min_element(our_count.begin(), our_count.end()));
  fmt::print("ours = {:.2f} Y (bar: well under 1 Y)\n", o / y);
  fmt::print(
      "descriptor spread (median Hamming of unrelated keypoints, ideal 128): ours {:.0f}, OpenCV {:.0f}\n",
      lrd::bench::median_of(our_spread), lrd::bench::median_of(cv_spread));
  return 0;
}
