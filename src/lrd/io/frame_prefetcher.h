#pragma once
// Decodes the frames of a FrameSource (a folder or a bag) ahead of the consumer on its own thread, into a
// bounded queue, so that PNG decoding overlaps tracking. Frames come out in sequence order.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "lrd/io/frame_source.h"
#include "lrd/io/rgbd_frame.h"
#include "lrd/io/tum_sequence.h"

namespace lrd::io {

struct PrefetchOptions {
  std::size_t queue_depth = 8;  // decoded frames held ahead of the consumer (>= 1)
  std::size_t begin = 0;        // first frame index
  std::size_t end = std::numeric_limits<std::size_t>::max();  // one past the last (clamped)
};

// Time spent in the decoder thread, so throughput with I/O can be reported apart from tracking.
struct DecodeStats {
  std::size_t frames = 0;       // frames decoded so far
  double decode_seconds = 0.0;  // total time spent decoding them
  double wait_seconds = 0.0;    // total time next() blocked waiting for a frame (I/O-bound time)
};

class FramePrefetcher {
 public:
  // Starts decoding at once. depth_factor: see FrameSource::load_rgbd. Only the decoder thread
  // reads the source while the prefetcher lives.
  FramePrefetcher(std::shared_ptr<const FrameSource> source, double depth_factor,
                  PrefetchOptions options = {});
  FramePrefetcher(TumSequence sequence, double depth_factor, PrefetchOptions options = {})
      : FramePrefetcher(std::make_shared<const TumSequence>(std::move(sequence)), depth_factor, options) {}
  // Stops the decoder thread (after the frame it is decoding, if any) and joins it.
  ~FramePrefetcher();
  FramePrefetcher(const FramePrefetcher&) = delete;
  FramePrefetcher& operator=(const FramePrefetcher&) = delete;

  // The next frame in order, blocking until it is decoded; nullopt after the last one. A decode
  // error is rethrown here (the same lrd::Error) once the frames before it have been returned,
  // and again on every later call.
  [[nodiscard]] std::optional<RgbdFrame> next();

  // Blocks until every frame is decoded (or decoding failed; next() then rethrows). With a queue
  // as deep as the sequence this separates decoding from tracking entirely (`--preload`).
  void wait_until_decoded();

  [[nodiscard]] DecodeStats stats() const;
  // Frames this prefetcher will deliver in total.
  [[nodiscard]] std::size_t size() const { return end_ - begin_; }

 private:
  void run();

  const std::shared_ptr<const FrameSource> source_;
  const double depth_factor_;
  const std::size_t queue_depth_;
  const std::size_t begin_;
  const std::size_t end_;

  mutable std::mutex mutex_;
  std::condition_variable not_empty_;  // consumer waits: a frame, the end or an error
  std::condition_variable not_full_;   // producer waits: room in the queue or stop
  std::deque<RgbdFrame> queue_;
  bool stop_ = false;
  bool done_ = false;
  std::exception_ptr error_;
  DecodeStats stats_;
  std::thread thread_;  // last: started once everything above is initialised
};

}  // namespace lrd::io
