#pragma once
// Training data for the segmentation network in the Pascal VOC layout, rendered by the synthetic
// benchmark: JPEGImages/*.jpg, SegmentationClassAug/*.png (grey index PNGs, VOC class ids;
// person 15, chair 9, dining table 11, sofa 18, potted plant 16, tv/monitor 20, everything else 0
// — a carried carton is background, as for a VOC-trained network), ImageSets/Segmentation/
// {train,val}.txt. Seeds start at kFirstSeed, disjoint from the benchmark's evaluation seeds
// (1..999), so a network trained here is never evaluated on frames it has seen.
#include <cstdint>
#include <filesystem>
#include <functional>

namespace lrd::synth {

inline constexpr std::uint64_t kFirstTrainingSeed = 1000;

struct VocExportOptions {
  int images = 2000;
  std::uint64_t first_seed = kFirstTrainingSeed;
  int frames_per_sequence = 25;  // sampled at random from each (preset, seed) sequence
  double val_fraction = 0.1;
};

struct VocExportSummary {
  int train = 0, val = 0;
  double person_pixel_fraction = 0.0;
  double seconds = 0.0;
};

VocExportSummary export_voc(const std::filesystem::path& dir, const VocExportOptions& options,
                            const std::function<void(int, int)>& progress = {});

}  // namespace lrd::synth
