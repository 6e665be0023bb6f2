// System::save_map and System::load_map (issue 20): the map outlives the process.
#include <spdlog/spdlog.h>

#include <mutex>

#include "lrd/map/keyframe.h"
#include "lrd/map/map_file.h"
#include "lrd/system_impl.h"
#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"

namespace lrd {

map::MapFileHeader System::Impl::map_file_header() const {
  map::MapFileHeader header;
  header.camera = config.camera;
  if (vocabulary) {
    header.vocabulary_fingerprint = vocabulary->fingerprint();
    header.vocabulary_words = vocabulary->word_count();
  }
  return header;
}

void System::save_map(const std::filesystem::path& file) const {
  if (!impl_->vocabulary)
    throw file_error(file, "no vocabulary is loaded: a map saved without one could never be relocalized in");
  const map::MapFileHeader header = impl_->map_file_header();
  std::string bytes;
  {
    std::lock_guard lock(impl_->pipe->map.mutex());
    bytes = map::serialize_map(impl_->pipe->map, header);
  }
  util::write_file_bytes(file, bytes);
}

void System::load_map(const std::filesystem::path& file) {
  Impl& s = *impl_;
  if (s.shut_down) throw file_error(file, "cannot load a map: the system has been shut down");
  if (!s.pipe->tracker.records().empty() || s.pipe->map.keyframe_count() != 0)
    throw file_error(file, "a map loads before the first frame only");
  if (!s.vocabulary)
    throw file_error(file, "a loaded map needs the vocabulary to relocalize in it, and none is loaded");
  // Into a pipeline of its own (the same map number: no frame has been seen), so that a bad file
  // leaves the system as it was.
  std::unique_ptr<Pipeline> fresh = s.make_pipeline(s.pipe->generation);
  {
    std::lock_guard lock(fresh->map.mutex());
    (void)map::load_map_file(file, fresh->map,
                             map::MapFileExpectation{s.config.camera, s.vocabulary->fingerprint()});
    // Bag-of-words vectors are not in the file: they follow from the vocabulary.
    for (map::KeyFrame* kf : fresh->map.keyframes()) {
      kf->compute_bow(*s.vocabulary);
      fresh->database.add(kf);
    }
    fresh->tracker.start_in_loaded_map();
  }
  s.pipe->shutdown();
  s.pipe = std::move(fresh);
  s.loaded_keyframes = s.pipe->map.keyframe_count();
  s.loaded_map_points = s.pipe->map.map_point_count();
  spdlog::info("{}: loaded {} keyframes and {} map points{}", file.string(), s.loaded_keyframes,
               s.loaded_map_points, s.options.localization_only ? " (localization only)" : "");
}

bool System::localization_only() const {
  return impl_->options.localization_only;
}

}  // namespace lrd
