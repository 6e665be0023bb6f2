#pragma once
// Benchmarks' synthetic sequences: generated once into a cache folder (seed 1), and the
// yardstick Y measured on each sequence's own grey frames.
#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "bench/yardstick.h"
#include "lrd/config/orbslam_settings.h"
#include "lrd/io/tum_sequence.h"
#include "lrd/synth/realism.h"
#include "lrd/synth/sequence_writer.h"
#include "lrd/synth/synthetic_sequence.h"

namespace lrd::bench {

// Whether the sequence in `dir` was rendered with every effect and parameter of `realism` as it
// is now (sequence.json's realism record; none for the clean profile).
inline bool realism_matches(const std::filesystem::path& dir, const lrd::synth::RealismParams& realism) {
  std::ifstream in(dir / "sequence.json");
  const auto meta = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (meta.is_discarded()) return false;
  if (realism.is_clean()) return !meta.contains("realism");
  if (!meta.contains("realism")) return false;
  nlohmann::json recorded = meta["realism"];
  recorded.erase("camera_motion");  // what the writer measured, beside the parameters
  if (recorded != lrd::synth::realism_json(realism)) return false;
  // settings.yaml gained the rolling shutter's readout time after the first `tum` renders.
  try {
    const double readout = lrd::config::read_orbslam_settings(dir / "settings.yaml").camera.readout_time;
    return readout == (realism.rolling_shutter ? realism.readout_time : 0.0);
  } catch (const std::exception&) {
    return false;
  }
}

// cache/PRESET (or cache/PRESET_FRAMES for a prefix; _sN for map-file session N > 1; _tum for
// the `tum` realism profile), rendered when absent.
inline std::filesystem::path ensure_sequence(const std::filesystem::path& cache, const std::string& preset,
                                             int frames, int session = 1,
                                             const std::string& realism = "clean") {
  std::string name = frames > 0 ? fmt::format("{}_{}", preset, frames) : preset;
  if (session != 1) name += fmt::format("_s{}", session);
  if (realism != "clean") name += "_" + realism;
  const std::filesystem::path dir = cache / name;
  lrd::synth::SynthOptions o;
  o.preset = preset;
  o.seed = 1;
  o.frames = frames;
  o.session = session;
  o.realism = lrd::synth::realism_profile(realism);
  // scene.ply came later than the first cached sequences, and the realism profile grows: those
  // are rendered again.
  if (std::filesystem::exists(dir / "associations.txt") && std::filesystem::exists(dir / "scene.ply") &&
      realism_matches(dir, o.realism))
    return dir;
  std::fprintf(stderr, "generating %s into %s ...\n", preset.c_str(), dir.string().c_str());
  const lrd::synth::SyntheticSequence seq(o);
  (void)lrd::synth::write_sequence(seq, dir);
  return dir;
}

// Y on (up to) 100 evenly spread grey frames of the sequence in `dir`.
inline double sequence_yardstick_ms(const std::filesystem::path& dir) {
  const auto seq = lrd::io::TumSequence::open(dir);
  std::vector<cv::Mat> grey;
  const std::size_t step = std::max<std::size_t>(1, seq.size() / 100);
  for (std::size_t i = 0; i < seq.size(); i += step)
    grey.push_back(cv::imread(seq.entry(i).rgb_path.string(), cv::IMREAD_GRAYSCALE));
  return yardstick_ms(grey);
}

}  // namespace lrd::bench
