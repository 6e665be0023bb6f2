#pragma once
// A TUM RGB-D benchmark sequence folder: rgb.txt and depth.txt ("timestamp filename" lines, '#'
// comments) associated like TUM's associate.py, or a ready associations.txt
// ("t_rgb rgb_path t_depth depth_path"), plus an optional groundtruth.txt.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <utility>
#include <vector>

#include "lrd/io/frame_source.h"
#include "lrd/io/rgbd_frame.h"

namespace lrd::io {

class TumSequence final : public FrameSource {
 public:
  // Reads the sequence in `dir`. With associations.txt present it is used as is; otherwise each
  // rgb image is paired with a depth image |t_rgb - t_depth| < max_dt apart, exactly as
  // associate.py does (candidate pairs sorted by (difference, t_rgb, t_depth), taken greedily
  // one-to-one, result sorted by rgb time). Throws lrd::Error ("FILE[:LINE]: problem") for a
  // missing folder or list file, a malformed line, unsorted or duplicate timestamps, an empty
  // result and a listed image file that does not exist.
  [[nodiscard]] static TumSequence open(const std::filesystem::path& dir, double max_dt = 0.02);

  [[nodiscard]] std::size_t size() const override { return entries_.size(); }
  [[nodiscard]] const FrameEntry& entry(std::size_t i) const override { return entries_.at(i); }
  [[nodiscard]] const std::vector<FrameEntry>& entries() const { return entries_; }
  [[nodiscard]] const std::filesystem::path& dir() const { return dir_; }
  // groundtruth.txt when the folder has one (read it with lrd::io::read_trajectory_tum).
  [[nodiscard]] const std::optional<std::filesystem::path>& groundtruth_path() const { return groundtruth_; }

  // Decodes frame i (see load_rgbd_frame); depth_factor is the PNG value per metre (5000 for TUM).
  [[nodiscard]] RgbdFrame load_rgbd(std::size_t i, double depth_factor) const override;

  // FrameSource: the colour image's file, the folder, groundtruth.txt read when asked.
  [[nodiscard]] std::string describe(std::size_t i) const override { return entry(i).rgb_path.string(); }
  [[nodiscard]] std::filesystem::path path() const override { return dir_; }
  [[nodiscard]] std::optional<std::filesystem::path> folder() const override { return dir_; }
  [[nodiscard]] std::optional<Trajectory> ground_truth() const override;
  [[nodiscard]] std::string ground_truth_origin() const override;

 private:
  std::filesystem::path dir_;
  std::vector<FrameEntry> entries_;
  std::optional<std::filesystem::path> groundtruth_;
};

// associate.py's rule (see TumSequence::open) on two sorted, strictly increasing timestamp lists:
// the (rgb index, depth index) pairs, in rgb order. Readers of other layouts (bags) use it so
// that the same frames pair alike everywhere.
[[nodiscard]] std::vector<std::pair<std::size_t, std::size_t>> associate_timestamps(
    const std::vector<double>& rgb, const std::vector<double>& depth, double max_dt);

}  // namespace lrd::io
