// `lrdslam vocab`: train the bag-of-words vocabulary that place recognition uses, from one's own
// images (ORB features as SLAM extracts them), and describe a vocabulary file.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "app/commands.h"
#include "lrd/features/orb_extractor.h"
#include "lrd/place/vocabulary.h"
#include "lrd/util/error.h"

namespace lrd::app {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxSide = 640;  // images are shrunk to this longer side, about a SLAM camera's

struct VocabCli {
  std::string images, out, file;
  int k = 10, levels = 5, features = 1000, max_images = 0, iterations = 10;
  std::uint64_t seed = 0x5eed;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

bool is_image(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg";
}

// A folder: its .png/.jpg/.jpeg files at any depth, sorted. A file: one image path a line ('#'
// starts a comment; relative paths are relative to the list's folder).
std::vector<fs::path> image_paths(const fs::path& source) {
  std::error_code ec;
  std::vector<fs::path> paths;
  if (fs::is_directory(source, ec)) {
    for (auto it =
             fs::recursive_directory_iterator(source, fs::directory_options::skip_permission_denied, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
      if (it->is_regular_file(ec) && is_image(it->path())) paths.push_back(it->path());
    if (ec) throw file_error(source, "cannot list the folder: " + ec.message());
    std::sort(paths.begin(), paths.end());
    if (paths.empty()) throw file_error(source, "no .png, .jpg or .jpeg images in this folder");
    return paths;
  }
  std::ifstream in(source);
  if (!in) throw file_error(source, "no such image list or folder");
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    const fs::path p = line.substr(first, line.find_last_not_of(" \t\r") - first + 1);
    paths.push_back(p.is_absolute() ? p : source.parent_path() / p);
  }
  if (paths.empty()) throw file_error(source, "the image list names no images");
  return paths;
}

// At most `max` of `paths`, evenly spaced (a sequence's frames spread over all of it).
std::vector<fs::path> subsample(const std::vector<fs::path>& paths, int max) {
  if (max <= 0 || paths.size() <= static_cast<std::size_t>(max)) return paths;
  std::vector<fs::path> out;
  for (int i = 0; i < max; ++i) out.push_back(paths[i * paths.size() / static_cast<std::size_t>(max)]);
  return out;
}

cv::Mat load_grey(const fs::path& file) {
  cv::Mat grey;
  try {
    grey = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception&) {
    return {};
  }
  const int side = std::max(grey.cols, grey.rows);
  if (side > kMaxSide) {
    const double s = static_cast<double>(kMaxSide) / side;
    const cv::Size size(std::max(1, static_cast<int>(grey.cols * s + 0.5)),
                        std::max(1, static_cast<int>(grey.rows * s + 0.5)));
    cv::resize(grey, grey, size, 0, 0, cv::INTER_AREA);
  }
  return grey;
}

// "4.07 MB (4065736 bytes)"
std::string size_text(const fs::path& file) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec) return "size unknown";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f MB (%ju bytes)", static_cast<double>(size) / 1e6, size);
  return buf;
}

void train(const VocabCli& cli) {
  const std::vector<fs::path> listed = image_paths(cli.images);
  const std::vector<fs::path> paths = subsample(listed, cli.max_images);
  features::OrbParams orb_params;
  orb_params.n_features = cli.features;
  features::OrbExtractor orb(orb_params);

  const auto t0 = std::chrono::steady_clock::now();
  std::vector<cv::Mat> descriptors;
  std::size_t total = 0;
  for (const fs::path& p : paths) {
    const cv::Mat grey = load_grey(p);
    if (grey.empty()) {
      spdlog::warn("{}: cannot read this image, skipped", p.string());
      continue;
    }
    std::vector<cv::KeyPoint> keypoints;
    cv::Mat d;
    orb.extract(grey, cv::Mat(), keypoints, d);
    if (d.rows == 0) {
      spdlog::warn("{}: no ORB features, skipped", p.string());
      continue;
    }
    total += static_cast<std::size_t>(d.rows);
    descriptors.push_back(d);
  }
  if (descriptors.empty())
    throw file_error(cli.images, "none of its " + std::to_string(paths.size()) + " images gave ORB features");
  const double extract_s = seconds_since(t0);
  std::printf("images: %zu used of %zu listed (%zu tried), %zu descriptors, extracted in %.1f s\n",
              descriptors.size(), listed.size(), paths.size(), total, extract_s);

  place::VocabularyParams params;
  params.k = cli.k;
  params.levels = cli.levels;
  params.max_iterations = cli.iterations;
  params.seed = cli.seed;
  const auto t1 = std::chrono::steady_clock::now();
  const place::Vocabulary vocab = place::Vocabulary::train(descriptors, params);
  const double train_s = seconds_since(t1);

  const fs::path out(cli.out);
  std::error_code ec;
  if (out.has_parent_path()) fs::create_directories(out.parent_path(), ec);
  vocab.save(out);
  std::printf("vocabulary: k %d, levels %d, %zu nodes, %zu words, trained in %.1f s\n", vocab.k(),
              vocab.levels(), vocab.node_count(), vocab.word_count(), train_s);
  std::printf("wrote %s, %s\n", out.string().c_str(), size_text(out).c_str());
}

void info(const VocabCli& cli) {
  const auto t0 = std::chrono::steady_clock::now();
  const place::Vocabulary vocab = place::Vocabulary::load(cli.file);
  const double load_ms = 1e3 * seconds_since(t0);
  std::vector<double> w(vocab.word_count());
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = vocab.word_weight(static_cast<place::WordId>(i));
  std::sort(w.begin(), w.end());
  std::printf("%s: %s, loaded in %.1f ms\n", cli.file.c_str(), size_text(cli.file).c_str(), load_ms);
  std::printf("k %d, levels %d, %zu nodes, %zu words\n", vocab.k(), vocab.levels(), vocab.node_count(),
              vocab.word_count());
  std::printf("idf weights: min %.3f, median %.3f, max %.3f\n", w.front(), w[w.size() / 2], w.back());
}

}  // namespace

void register_vocab_command(CLI::App& app) {
  auto cli = std::make_shared<VocabCli>();
  CLI::App* cmd = app.add_subcommand("vocab", "Train or describe a bag-of-words vocabulary of ORB features");
  cmd->require_subcommand(1);

  CLI::App* tr =
      cmd->add_subcommand("train", "Train a vocabulary from images (ORB features, hierarchical k-medians)");
  tr->add_option(
        "--images", cli->images,
        "A folder (searched recursively for .png/.jpg/.jpeg) or a text file with one image path a line")
      ->required();
  tr->add_option("--out", cli->out, "Vocabulary file to write (.lrdv)")->required();
  tr->add_option("--k", cli->k, "Branching factor")->check(CLI::Range(2, 65536))->capture_default_str();
  tr->add_option("--levels", cli->levels, "Depth of the tree")
      ->check(CLI::Range(1, 32))
      ->capture_default_str();
  tr->add_option("--features", cli->features, "ORB features per image")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  tr->add_option("--max-images", cli->max_images, "Use at most this many images, evenly spaced (0: all)")
      ->check(CLI::Range(0, 1 << 30))
      ->capture_default_str();
  tr->add_option("--iterations", cli->iterations, "Lloyd iterations per node")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  tr->add_option("--seed", cli->seed, "Seed of the clustering (same images and seed: same file)")
      ->capture_default_str();
  tr->callback([cli] { train(*cli); });

  CLI::App* in = cmd->add_subcommand("info", "Print a vocabulary's size, shape and load time");
  in->add_option("file", cli->file, "Vocabulary file (.lrdv)")->required();
  in->callback([cli] { info(*cli); });
}

}  // namespace lrd::app
