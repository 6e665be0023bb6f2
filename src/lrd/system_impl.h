#pragma once
// lrd::System's state (internal): the parameters read once, the vocabulary, the publisher and the
// thread-error sink that outlive reset(), and the Pipeline of the current map.
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <mutex>
#include <opencv2/features2d.hpp>
#include <string>

#include "lrd/map/map_file.h"
#include "lrd/pipeline.h"
#include "lrd/system.h"

namespace lrd {

struct System::Impl {
  Impl(const config::Config& cfg, SystemParams p, SystemOptions opts);
  void start_pipeline();
  // A Pipeline for map number `generation` (threads started), not yet in use.
  [[nodiscard]] std::unique_ptr<Pipeline> make_pipeline(std::uint32_t generation);
  // What a map file records beside the map: camera and vocabulary (system_maps.cc).
  [[nodiscard]] map::MapFileHeader map_file_header() const;
  // The vocabulary's fingerprint, hashed once (its whole file's bytes: too slow for every autosave).
  [[nodiscard]] std::uint64_t vocabulary_fingerprint() const;

  TrackResult track(const cv::Mat& rgb, const cv::Mat& depth, double timestamp, const cv::Mat& mask);
  void publish_frame(const TrackResult& r, const tracking::TrackOutcome& outcome, const data::Frame& frame,
                     const cv::Mat& grey, bool grey_shared);

  config::Config config;
  SystemParams params;
  SystemOptions options;
  std::filesystem::path vocabulary_file;
  std::shared_ptr<const place::Vocabulary> vocabulary;
  util::ThreadErrors errors;
  events::EventPublisher publisher;  // before `pipe`: its threads publish until they stop
  dense::DenseMapper::RepairCallback repair_callback;
  std::unique_ptr<Pipeline> pipe;
  std::uint32_t next_generation = 0;  // the next Pipeline's map number
  std::uint64_t next_frame_id = 0;
  double last_timestamp = -std::numeric_limits<double>::infinity();
  bool shut_down = false;
  std::size_t loaded_keyframes = 0, loaded_map_points = 0;  // load_map()
  std::string failure;                   // the error track_rgbd threw that stopped the system (empty: none)
  cv::Ptr<cv::Feature2D> yardstick_orb;  // SystemOptions::yardstick: OpenCV's ORB, Y's definition
  mutable std::once_flag fingerprint_once;
  mutable std::uint64_t fingerprint = 0;
};

}  // namespace lrd
