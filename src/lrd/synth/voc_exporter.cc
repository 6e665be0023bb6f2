#include "lrd/synth/voc_exporter.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <mutex>
#include <opencv2/imgcodecs.hpp>

#include "lrd/io/image_file.h"
#include "lrd/synth/portable_random.h"
#include "lrd/synth/presets.h"
#include "lrd/synth/synthetic_sequence.h"
#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"

namespace lrd::synth {
namespace fs = std::filesystem;

VocExportSummary export_voc(const fs::path& dir, const VocExportOptions& options,
                            const std::function<void(int, int)>& progress) {
  if (options.images <= 0) throw Error("synth --export-voc: the number of images must be positive");
  if (options.first_seed < kFirstTrainingSeed)
    throw Error(
        fmt::format("synth --export-voc: seeds below {} are reserved for evaluation", kFirstTrainingSeed));
  const auto start = std::chrono::steady_clock::now();
  for (const char* sub : {"JPEGImages", "SegmentationClassAug", "ImageSets/Segmentation"}) {
    std::error_code ec;
    fs::create_directories(dir / sub, ec);
    if (ec) throw file_error(dir / sub, "cannot create folder: " + ec.message());
  }
  // Every preset with people, cycled; the empty-room ones add background-only examples. The long
  // preset came after FNet-lite was trained: left out, the draw stays the same.
  std::vector<PresetSpec> specs;
  for (const PresetSpec& s : preset_specs())
    if (!s.held_out) specs.push_back(s);
  const auto textures = SyntheticSequence::load_textures();
  const int per_seq = std::max(1, options.frames_per_sequence);
  const int sequences = (options.images + per_seq - 1) / per_seq;
  std::vector<std::string> names(static_cast<std::size_t>(options.images));
  std::vector<double> person(static_cast<std::size_t>(options.images), 0.0);
  std::mutex progress_mutex;
  int done = 0;
  tbb::parallel_for(0, sequences, [&](int s) {
    SynthOptions o;
    o.preset = specs[static_cast<std::size_t>(s) % specs.size()].name;
    o.seed = options.first_seed + static_cast<std::uint64_t>(s);
    o.frames = -1;
    const SyntheticSequence seq(o, textures);
    PortableRandom rng(o.seed);
    for (int k = 0; k < per_seq; ++k) {
      const int image = s * per_seq + k;
      if (image >= options.images) break;
      const int frame = static_cast<int>(rng.pick(static_cast<std::size_t>(seq.size())));
      const SynthFrame f = seq.render(frame);
      const std::string name = fmt::format("synth_{}_{}_{:04d}", o.preset, o.seed, frame);
      // Thousands of images a rerun makes again: not synced one by one (util::Sync).
      io::write_image_file(dir / "JPEGImages" / (name + ".jpg"), f.rgb, {cv::IMWRITE_JPEG_QUALITY, 95},
                           util::Sync::no);
      io::write_image_file(dir / "SegmentationClassAug" / (name + ".png"), f.voc_class, {}, util::Sync::no);
      names[static_cast<std::size_t>(image)] = name;
      person[static_cast<std::size_t>(image)] =
          cv::countNonZero(f.voc_class == 15) / static_cast<double>(f.voc_class.total());
      if (progress) {
        std::lock_guard lock(progress_mutex);
        progress(++done, options.images);
      }
    }
  });
  // Whole sequences go to validation, so no val frame has a near-duplicate in train.
  VocExportSummary summary;
  std::string train, val;
  const int val_every =
      options.val_fraction > 0 ? std::max(2, static_cast<int>(1.0 / options.val_fraction)) : 0;
  for (int i = 0; i < options.images; ++i) {
    const int seq = i / per_seq;
    // Every val_every-th sequence; with fewer sequences than that, the last one (if not the only).
    const bool is_val = val_every > 0 && (seq % val_every == val_every - 1 ||
                                          (sequences < val_every && sequences > 1 && seq == sequences - 1));
    (is_val ? val : train) += names[static_cast<std::size_t>(i)] + '\n';
    (is_val ? summary.val : summary.train) += 1;
    summary.person_pixel_fraction += person[static_cast<std::size_t>(i)] / options.images;
  }
  util::write_file_bytes(dir / "ImageSets/Segmentation/train.txt", train);
  util::write_file_bytes(dir / "ImageSets/Segmentation/val.txt", val);
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace lrd::synth
