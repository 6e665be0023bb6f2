#pragma once
// A synthetic sequence as a run's frame source (`lrdslam run --synth PRESET`): each frame is
// rendered when the run's decoding thread asks for it, so a run of any length needs no disk but
// its outputs. The frames equal those `lrdslam synth` writes (same preset, seed and session), read
// back from their PNGs; the ground truth is the poses groundtruth.txt would hold.
#include <memory>
#include <string>

#include "lrd/io/frame_source.h"
#include "lrd/synth/synthetic_sequence.h"

namespace lrd::synth {

class SyntheticSource : public io::FrameSource {
 public:
  // Throws lrd::Error for an unknown preset or a bad option (as `lrdslam synth` does).
  explicit SyntheticSource(const SynthOptions& options);

  [[nodiscard]] std::size_t size() const override { return entries_.size(); }
  [[nodiscard]] const io::FrameEntry& entry(std::size_t i) const override { return entries_.at(i); }
  // Renders frame i: BGR colour and depth in metres (the sequence's own depth unit; the
  // depth_factor argument is for files and is ignored).
  [[nodiscard]] io::RgbdFrame load_rgbd(std::size_t i, double depth_factor) const override;
  [[nodiscard]] std::string describe(std::size_t i) const override;
  // "synth:PRESET?seed=S&session=N&frames=F": what summary.json records as the sequence.
  [[nodiscard]] std::filesystem::path path() const override { return name_; }
  [[nodiscard]] std::optional<std::filesystem::path> folder() const override { return std::nullopt; }
  [[nodiscard]] std::optional<io::Trajectory> ground_truth() const override { return ground_truth_; }
  [[nodiscard]] std::string ground_truth_origin() const override { return name_ + " (rendered poses)"; }
  // The synthetic camera (TUM fr3's intrinsics, no distortion): settings.yaml's camera.
  [[nodiscard]] std::optional<io::SourceCamera> camera() const override;
  [[nodiscard]] bool synthetic_benchmark() const override { return true; }

  [[nodiscard]] const SyntheticSequence& sequence() const { return *sequence_; }

 private:
  std::unique_ptr<const SyntheticSequence> sequence_;
  std::string name_;
  std::vector<io::FrameEntry> entries_;
  io::Trajectory ground_truth_;
};

}  // namespace lrd::synth
