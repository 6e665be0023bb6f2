#pragma once
// The segmentation thread (paper Fig. 1): each frame's colour image is handed over the moment the
// frame arrives, so the network runs while tracking extracts ORB features. Tracking then asks
// for the mask:
//  - sync: waits until the mask of this very frame is ready (the paper's schedule);
//  - async: waits at most a bounded time, then takes the newest finished mask (an older frame's);
//    while the network is busy only the newest request is kept, older ones are skipped.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "lrd/segmentation/segmentation_params.h"
#include "lrd/segmentation/segmenter.h"

namespace lrd::segmentation {

struct SegmentationResult {
  std::uint64_t frame_id = 0;
  double timestamp = 0.0;
  cv::Mat mask;          // CV_8UC1, 255 = dynamic, as the segmenter gave it (not dilated)
  double seconds = 0.0;  // time the segmenter took
};

class SegmentationWorker {
 public:
  SegmentationWorker(std::unique_ptr<Segmenter> segmenter, Schedule schedule, bool rgb_order);
  ~SegmentationWorker();
  SegmentationWorker(const SegmentationWorker&) = delete;
  SegmentationWorker& operator=(const SegmentationWorker&) = delete;

  // Queues frame `frame_id` (ids increase); the image is shared, not copied: do not modify it.
  void submit(std::uint64_t frame_id, double timestamp, const cv::Mat& rgb);
  // The newest result for a frame <= frame_id, once frame_id's own is ready or `timeout_s` has
  // passed (no timeout: wait for it). Empty when nothing has finished yet. Rethrows the
  // segmenter's error (e.g. a missing mask file) as lrd::Error.
  [[nodiscard]] std::optional<SegmentationResult> wait(std::uint64_t frame_id,
                                                       std::optional<double> timeout_s);
  // Requests replaced by newer ones before the segmenter got to them (async only).
  [[nodiscard]] std::size_t skipped() const;
  [[nodiscard]] const Segmenter& segmenter() const { return *segmenter_; }
  [[nodiscard]] Schedule schedule() const { return schedule_; }

  void shutdown();

 private:
  struct Request {
    std::uint64_t frame_id;
    double timestamp;
    cv::Mat rgb;
  };
  void run();

  std::unique_ptr<Segmenter> segmenter_;
  Schedule schedule_;
  bool rgb_order_;
  mutable std::mutex mutex_;
  std::condition_variable request_ready_, result_ready_;
  std::deque<Request> requests_;
  std::optional<SegmentationResult> newest_;
  std::exception_ptr error_;
  std::size_t skipped_ = 0;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace lrd::segmentation
