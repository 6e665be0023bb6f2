// Bag-of-words vocabulary costs against the yardstick Y (median cv::ORB 1000/1.2/8
// detectAndCompute on the same frames): the file's size, its load time (the process's first load,
// then the median of 5), the time to turn one frame's ~1000 ORB descriptors into a BoW vector
// (with and without the direct index at data::Frame::kBowLevelsUp, as SLAM uses it), and the time to score
// two BoW vectors. Usage: bench_vocab [VOCAB_FILE]   (default: vocab/orb_vocab.lrdv of the project)
#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "bench/yardstick.h"
#include "lrd/data/frame.h"
#include "lrd/features/orb_extractor.h"
#include "lrd/place/vocabulary.h"
#include "lrd/synth/synthetic_sequence.h"
#include "lrd/util/error.h"
#include "lrd/util/project_files.h"

namespace {

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// Median milliseconds of `reps` calls of `f`.
template <class F>
double median_ms(int reps, F&& f) {
  std::vector<double> ms;
  for (int i = 0; i < reps; ++i) {
    const double t0 = now_ms();
    f();
    ms.push_back(now_ms() - t0);
  }
  return lrd::bench::median_of(ms);
}

}  // namespace

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  const fs::path file = argc > 1 ? fs::path(argv[1]) : lrd::util::find_project_file("vocab/orb_vocab.lrdv");
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) {
    fmt::print(stderr, "{}: no vocabulary file (train one: lrdslam vocab train --images DIR --out FILE)\n",
               file.string());
    return 1;
  }

  // Frames of the synthetic walking_xyz sequence: Y, and the descriptors to transform.
  lrd::synth::SynthOptions opt;
  opt.preset = "walking_xyz";
  const lrd::synth::SyntheticSequence seq(opt);
  std::vector<cv::Mat> greys;
  for (int i = 0; i < 10; ++i) {
    cv::Mat grey;
    cv::cvtColor(seq.render(i * 20).rgb, grey, cv::COLOR_BGR2GRAY);
    greys.push_back(grey);
  }
  const double y = lrd::bench::yardstick_ms(greys);

  try {
    lrd::place::Vocabulary vocab;
    // The first load in a process pays for fresh pages (most of it on a VM); later ones reuse them.
    const double first_load = median_ms(1, [&] { vocab = lrd::place::Vocabulary::load(file); });
    const double load = median_ms(5, [&] { vocab = lrd::place::Vocabulary::load(file); });

    lrd::features::OrbExtractor orb{lrd::features::OrbParams{}};
    std::vector<cv::KeyPoint> kps;
    cv::Mat a, b;
    orb.extract(greys[0], cv::Mat(), kps, a);
    orb.extract(greys[1], cv::Mat(), kps, b);
    lrd::place::BowVector bow, bow_b;
    lrd::place::FeatureVector fv;
    vocab.transform(b, bow_b);
    const double with_fv =
        median_ms(50, [&] { vocab.transform(a, bow, fv, lrd::data::Frame::kBowLevelsUp); });
    const double bow_only = median_ms(50, [&] { vocab.transform(a, bow); });
    double sink = 0.0;
    const double score = median_ms(200, [&] { sink += lrd::place::Vocabulary::score(bow, bow_b); });

    fmt::print("{}: {:.2f} MB, k {}, levels {}, {} nodes, {} words\n", file.string(),
               static_cast<double>(fs::file_size(file)) / 1e6, vocab.k(), vocab.levels(), vocab.node_count(),
               vocab.word_count());
    fmt::print("Y (cv::ORB 1000/1.2/8 detectAndCompute, {} synthetic frames {}x{}) median {:.2f} ms\n",
               greys.size(), greys[0].cols, greys[0].rows, y);
    fmt::print("first load                                        {:8.2f} ms = {:6.2f} Y\n", first_load,
               first_load / y);
    fmt::print("load                                 median of 5  {:8.2f} ms = {:6.2f} Y\n", load, load / y);
    fmt::print(
        "transform {} descriptors, bow + fv({}) median of 50 {:8.3f} ms = {:6.3f} Y ({} words, {} nodes)\n",
        a.rows, lrd::data::Frame::kBowLevelsUp, with_fv, with_fv / y, bow.size(), fv.size());
    fmt::print("transform {} descriptors, bow only    median of 50 {:8.3f} ms = {:6.3f} Y\n", a.rows,
               bow_only, bow_only / y);
    fmt::print("score of two frames' BoW vectors     median       {:8.4f} ms = {:6.4f} Y (score {:.3f})\n",
               score, score / y, sink / 200.0);
  } catch (const lrd::Error& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 1;
  }
  return 0;
}
