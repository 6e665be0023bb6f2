#include "lrd/synth/synthetic_source.h"

#include <fmt/format.h>

#include "lrd/io/rgbd_frame.h"
#include "lrd/synth/sequence_writer.h"
#include "lrd/util/error.h"

namespace lrd::synth {

SyntheticSource::SyntheticSource(const SynthOptions& options)
    : sequence_(std::make_unique<const SyntheticSequence>(options)),
      ground_truth_(sequence_->ground_truth()) {
  const SyntheticSequence& seq = *sequence_;
  name_ = fmt::format("synth:{}?seed={}&session={}&frames={}", seq.spec().name, options.seed, options.session,
                      seq.size());
  entries_.reserve(static_cast<std::size_t>(seq.size()));
  for (int i = 0; i < seq.size(); ++i) {
    // Named as the folder `lrdslam synth` writes names them: saved masks and repaired keyframes
    // of a streamed run match the written sequence's files.
    io::FrameEntry e;
    e.timestamp = seq.timestamp(i);
    e.depth_timestamp = seq.depth_timestamp(i);
    e.rgb_path = std::filesystem::path("rgb") / frame_file_name(e.timestamp);
    e.depth_path = std::filesystem::path("depth") / frame_file_name(e.depth_timestamp);
    entries_.push_back(std::move(e));
  }
}

io::RgbdFrame SyntheticSource::load_rgbd(std::size_t i, double /*depth_factor*/) const {
  if (i >= entries_.size()) throw Error(fmt::format("{}: no frame {} (of {})", name_, i, entries_.size()));
  const SynthFrame f = sequence_->render(static_cast<int>(i), SyntheticSequence::Views::CameraOnly);
  io::RgbdFrame frame;
  frame.index = i;
  frame.timestamp = f.timestamp;
  frame.rgb = f.rgb;
  frame.depth = io::depth_in_metres(f.depth, sequence_->camera().depth_map_factor);
  return frame;
}

std::string SyntheticSource::describe(std::size_t i) const {
  return fmt::format("{} frame {}", name_, i);
}

std::optional<io::SourceCamera> SyntheticSource::camera() const {
  const camera::PinholeCamera& c = sequence_->camera();
  const camera::Distortion& d = c.distortion;
  const std::string origin = "the synthetic camera of " + name_;
  return io::SourceCamera{c.width, c.height, c.fx, c.fy, c.cx,           c.cy,  d.k1,
                          d.k2,    d.p1,     d.p2, d.k3, c.readout_time, origin};
}

}  // namespace lrd::synth
