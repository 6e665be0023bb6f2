#pragma once
// A short static synthetic sequence rendered in memory once per test process (rendering dominates
// the test time under sanitizers), its colour already in the camera's order (RGB) for
// System::track_rgbd, with its ground truth.
#include <opencv2/imgproc.hpp>
#include <vector>

#include "lrd/config/config.h"
#include "lrd/io/trajectory.h"
#include "lrd/synth/synthetic_sequence.h"

namespace lrd::test {

struct RenderedSequence {
  camera::PinholeCamera camera;
  std::vector<synth::SynthFrame> frames;  // rgb in RGB order
  io::Trajectory ground_truth;
};

inline const RenderedSequence& static_sequence() {
  static const RenderedSequence seq = [] {
    synth::SynthOptions o;
    o.preset = "static_xyz";
    o.seed = 1;
    o.frames = 45;
    const synth::SyntheticSequence s(o);
    RenderedSequence r;
    r.camera = s.camera();
    for (int i = 0; i < s.size(); ++i) {
      r.frames.push_back(s.render(i));
      cv::cvtColor(r.frames.back().rgb, r.frames.back().rgb, cv::COLOR_BGR2RGB);  // the camera says RGB
      r.ground_truth.push_back({r.frames.back().timestamp, r.frames.back().pose});
    }
    return r;
  }();
  return seq;
}

inline config::Config config_for(const camera::PinholeCamera& camera) {
  config::Config c;
  c.camera = camera;
  return c;
}

}  // namespace lrd::test
