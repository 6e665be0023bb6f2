#pragma once
// `--realism` and `--realism-off` (docs/synthetic-benchmark.md), the same on `synth` and on
// `run --synth`.
#include <CLI/CLI.hpp>
#include <string>

#include "lrd/synth/realism.h"

namespace lrd::app {

struct RealismOptions {
  std::string profile = "clean";
  std::string off;

  // `needs`: the option the realism flags only make sense with (run's --synth), or null.
  void add_to(CLI::App* cmd, CLI::Option* needs) {
    auto* p = cmd->add_option(
                     "--realism", profile,
                     "Realism profile of the rendered frames: clean (the renderer's own), tum (as a Kinect "
                     "v1 in TUM RGB-D: exposure, blur, rolling shutter, Bayer noise, distortion, depth "
                     "registration, motion-capture ground truth; docs/synthetic-benchmark.md)")
                  ->check(CLI::IsMember({"clean", "tum"}))
                  ->capture_default_str();
    auto* o = cmd->add_option(
        "--realism-off", off,
        "With --realism tum: effects to leave out, comma-separated (" + synth::realism_effect_list() + ")");
    if (needs != nullptr) {
      p->needs(needs);
      o->needs(needs);
    }
  }
  [[nodiscard]] synth::RealismParams params() const {
    synth::RealismParams r = synth::realism_profile(profile);
    if (!off.empty()) synth::disable_realism_effects(r, off);
    return r;
  }
};

}  // namespace lrd::app
