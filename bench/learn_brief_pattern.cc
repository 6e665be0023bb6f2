// Learns the steered-BRIEF test pattern of src/lrd/features/brief_pattern.cc the way Rublee et al.
// 2011 (sec. 4.3) learn rBRIEF: on oriented keypoints from many images, rank candidate tests by how
// close their mean is to 0.5 (high variance) and greedily keep those whose correlation with every
// test kept so far stays under a threshold, raising the threshold until there are 256.
// Not a benchmark; run it to regenerate the table (about 2 minutes, libstdc++'s distributions):
//   learn_brief_pattern > pattern.txt
// Candidates: point pairs in the disc of radius 13, half from BRIEF's Gaussian (sigma 31/5), half
// uniform. Training images: frames of the synthetic static presets (photograph textures).
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "lrd/features/brief_pattern.h"
#include "lrd/features/gaussian_smoother.h"
#include "lrd/features/orb_extractor.h"
#include "lrd/synth/synthetic_sequence.h"

namespace {

constexpr int kR = lrd::features::kBriefRadius;
constexpr int kSide = 2 * kR + 1;
using Patch = std::array<std::uint8_t, kSide * kSide>;  // steered, smoothed, nearest sampling

// Steered patches of every keypoint of `grey`, sampled exactly as the extractor's descriptor.
void add_patches(const cv::Mat& grey, lrd::features::OrbExtractor& orb, std::vector<Patch>& out) {
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  orb.extract(grey, cv::Mat(), kps, desc);
  lrd::features::GaussianSmoother smoother;
  std::vector<cv::Mat> smoothed(orb.levels());
  for (int l = 0; l < orb.levels(); ++l) smoother.smooth(orb.pyramid().level(l), smoothed[l]);
  for (const cv::KeyPoint& kp : kps) {
    const cv::Mat& img = smoothed[kp.octave];
    const float rx = static_cast<float>(grey.cols) / static_cast<float>(img.cols);
    const float ry = static_cast<float>(grey.rows) / static_cast<float>(img.rows);
    const int cx = cvRound((kp.pt.x + 0.5f) / rx - 0.5f), cy = cvRound((kp.pt.y + 0.5f) / ry - 0.5f);
    const float t = kp.angle * std::numbers::pi_v<float> / 180.0f, c = std::cos(t), s = std::sin(t);
    Patch p{};
    for (int y = -kR; y <= kR; ++y) {
      for (int x = -kR; x <= kR; ++x) {
        const float fx = static_cast<float>(x) * c - static_cast<float>(y) * s;
        const float fy = static_cast<float>(x) * s + static_cast<float>(y) * c;
        const int sx = static_cast<int>(fx + std::copysign(0.5f, fx));
        const int sy = static_cast<int>(fy + std::copysign(0.5f, fy));
        p[(y + kR) * kSide + (x + kR)] = img.at<std::uint8_t>(cy + sy, cx + sx);
      }
    }
    out.push_back(p);
  }
}

}  // namespace

int main() {
  lrd::features::OrbExtractor orb{lrd::features::OrbParams{}};
  std::vector<Patch> patches;
  const auto textures = lrd::synth::SyntheticSequence::load_textures();
  for (const char* preset : {"static_xyz", "static_halfsphere", "static_loop"}) {
    lrd::synth::SynthOptions o;
    o.preset = preset;
    const lrd::synth::SyntheticSequence seq(o, textures);
    for (int i = 0; i < seq.size(); i += seq.size() / 20) {
      cv::Mat grey;
      cv::cvtColor(seq.render(i).rgb, grey, cv::COLOR_BGR2GRAY);
      add_patches(grey, orb, patches);
    }
  }
  const int n = static_cast<int>(patches.size());
  const int words = (n + 63) / 64;
  fmt::print(stderr, "{} training keypoints\n", n);

  // Candidate tests.
  std::mt19937_64 rng(20240611);
  std::normal_distribution<double> gauss(0.0, 31.0 / 5.0);
  std::uniform_int_distribution<int> uni(-kR, kR);
  auto point = [&](bool gaussian) {
    for (;;) {
      const int x = gaussian ? static_cast<int>(std::lround(gauss(rng))) : uni(rng);
      const int y = gaussian ? static_cast<int>(std::lround(gauss(rng))) : uni(rng);
      if (x * x + y * y <= kR * kR) return cv::Point(x, y);
    }
  };
  constexpr int kCandidates = 40000;
  std::vector<std::array<cv::Point, 2>> tests;
  while (static_cast<int>(tests.size()) < kCandidates) {
    const bool g = tests.size() % 2 == 0;
    const cv::Point a = point(g), b = point(g);
    if (a != b) tests.push_back({a, b});
  }
  std::vector<std::vector<std::uint64_t>> bits(kCandidates, std::vector<std::uint64_t>(words, 0));
  std::vector<double> mean(kCandidates, 0.0);
  for (int t = 0; t < kCandidates; ++t) {
    const int ia = (tests[t][0].y + kR) * kSide + tests[t][0].x + kR;
    const int ib = (tests[t][1].y + kR) * kSide + tests[t][1].x + kR;
    int ones = 0;
    for (int k = 0; k < n; ++k) {
      if (patches[k][ia] < patches[k][ib]) {
        bits[t][k / 64] |= 1ull << (k % 64);
        ++ones;
      }
    }
    mean[t] = static_cast<double>(ones) / n;
  }
  std::vector<int> order(kCandidates);
  for (int t = 0; t < kCandidates; ++t) order[t] = t;
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return std::abs(mean[a] - 0.5) < std::abs(mean[b] - 0.5); });
  fmt::print(stderr, "{} of {} candidates with |mean - 0.5| < 0.1\n",
             std::count_if(mean.begin(), mean.end(), [](double m) { return std::abs(m - 0.5) < 0.1; }),
             kCandidates);
  auto correlation = [&](int a, int b) {
    int both = 0;
    for (int w = 0; w < words; ++w) both += std::popcount(bits[a][w] & bits[b][w]);
    const double pa = mean[a], pb = mean[b], pab = static_cast<double>(both) / n;
    return (pab - pa * pb) / std::sqrt(pa * (1 - pa) * pb * (1 - pb));
  };
  std::vector<int> chosen;
  for (double threshold = 0.2; chosen.size() < 256; threshold += 0.025) {
    chosen.clear();
    for (int t : order) {
      if (chosen.size() == 256) break;
      bool ok = true;
      for (int c : chosen) {
        if (std::abs(correlation(t, c)) > threshold) {
          ok = false;
          break;
        }
      }
      if (ok) chosen.push_back(t);
    }
    fmt::print(stderr, "threshold {:.3f}: {} tests\n", threshold, chosen.size());
  }
  double bias = 0.0;
  for (int c : chosen) bias += std::abs(mean[c] - 0.5);
  fmt::print(stderr, "mean |bit mean - 0.5| {:.4f}\n", bias / 256);
  for (int i = 0; i < 256; ++i) {
    const auto& t = tests[chosen[i]];
    fmt::print("{{{}, {}, {}, {}}},{}", t[0].x, t[0].y, t[1].x, t[1].y, i % 6 == 5 ? "\n" : " ");
  }
  fmt::print("\n");
  return 0;
}
