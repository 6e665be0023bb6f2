// System::save_map and System::load_map (docs/map-files.md): the map outlives the process.
#include <spdlog/spdlog.h>

#include <chrono>
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
    header.vocabulary_fingerprint = vocabulary_fingerprint();
    header.vocabulary_words = vocabulary->word_count();
  }
  return header;
}

std::uint64_t System::Impl::vocabulary_fingerprint() const {
  std::call_once(fingerprint_once, [this] { fingerprint = vocabulary ? vocabulary->fingerprint() : 0; });
  return fingerprint;
}

// What a PendingMapSave holds: the copy, and its place among the map's reclamation participants.
struct PendingMapSave::State {
  map::Reclamation* reclamation = nullptr;
  map::Reclamation::Participant participant = 0;
  map::MapCapture capture;
};

PendingMapSave::PendingMapSave(std::unique_ptr<State> state, double lock_seconds)
    : state_(std::move(state)), lock_seconds_(lock_seconds) {}

PendingMapSave::~PendingMapSave() {
  if (state_) state_->reclamation->leave(state_->participant);
}

std::string PendingMapSave::serialize() const {
  return map::serialize_capture(state_->capture);
}

PendingMapSave System::capture_map() const {
  if (!impl_->vocabulary)
    throw Error("no vocabulary is loaded: a map saved without one could never be relocalized in");
  using Clock = std::chrono::steady_clock;
  map::Map& map = impl_->pipe->map;
  auto state = std::make_unique<PendingMapSave::State>();
  const map::MapFileHeader header = impl_->map_file_header();
  // The keyframes' features are read after the mutex is released: taking part in reclamation
  // keeps a keyframe culled meanwhile from being freed until the save is done with it.
  state->reclamation = &map.reclamation();
  state->participant = state->reclamation->join("map save");
  double lock_seconds = 0.0;
  try {
    std::lock_guard lock(map.mutex());
    const auto t0 = Clock::now();
    state->capture = map::capture_map(map, header);
    lock_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  } catch (...) {
    state->reclamation->leave(state->participant);
    throw;
  }
  return PendingMapSave(std::move(state), lock_seconds);
}

void System::save_map(const std::filesystem::path& file) const {
  if (!impl_->vocabulary)
    throw file_error(file, "no vocabulary is loaded: a map saved without one could never be relocalized in");
  std::string bytes;
  {
    const PendingMapSave pending = capture_map();
    bytes = pending.serialize();
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
                             map::MapFileExpectation{s.config.camera, s.vocabulary_fingerprint()});
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
