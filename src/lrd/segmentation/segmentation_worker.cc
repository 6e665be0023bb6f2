#include "lrd/segmentation/segmentation_worker.h"

#include <chrono>

#include "lrd/util/error.h"
#include "lrd/util/exception_message.h"
#include "lrd/util/fault_injection.h"
#include "lrd/util/thread_priority.h"

namespace lrd::segmentation {

SegmentationWorker::SegmentationWorker(std::unique_ptr<Segmenter> segmenter, Schedule schedule,
                                       bool rgb_order)
    : segmenter_(std::move(segmenter)), schedule_(schedule), rgb_order_(rgb_order) {
  thread_ = std::thread([this] { run(); });
}

SegmentationWorker::~SegmentationWorker() {
  shutdown();
}

void SegmentationWorker::shutdown() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  request_ready_.notify_all();
  result_ready_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void SegmentationWorker::submit(std::uint64_t frame_id, double timestamp, const cv::Mat& rgb) {
  {
    std::lock_guard lock(mutex_);
    if (schedule_ == Schedule::Async && !requests_.empty()) {
      skipped_ += requests_.size();
      requests_.clear();
    }
    requests_.push_back({frame_id, timestamp, rgb});
  }
  request_ready_.notify_one();
}

std::size_t SegmentationWorker::skipped() const {
  std::lock_guard lock(mutex_);
  return skipped_;
}

std::optional<SegmentationResult> SegmentationWorker::wait(std::uint64_t frame_id,
                                                           std::optional<double> timeout_s) {
  std::unique_lock lock(mutex_);
  auto done = [&] { return error_ || stop_ || (newest_ && newest_->frame_id >= frame_id); };
  if (timeout_s) {
    result_ready_.wait_for(lock, std::chrono::duration<double>(*timeout_s), done);
  } else {
    result_ready_.wait(lock, done);
  }
  if (error_) std::rethrow_exception(error_);
  if (newest_ && newest_->frame_id > frame_id) return std::nullopt;  // cannot happen: ids increase
  return newest_;
}

void SegmentationWorker::run() {
  util::name_this_thread("lrd-segment");
  for (;;) {
    Request req;
    {
      std::unique_lock lock(mutex_);
      request_ready_.wait(lock, [&] { return stop_ || !requests_.empty(); });
      if (stop_) return;
      req = std::move(requests_.front());
      requests_.pop_front();
    }
    SegmentationResult result;
    result.frame_id = req.frame_id;
    result.timestamp = req.timestamp;
    try {
      const auto t0 = std::chrono::steady_clock::now();
      util::check_fault_point("segmentation");
      result.mask = segmenter_->segment(req.rgb, rgb_order_, req.timestamp);
      result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    } catch (const Error&) {
      std::lock_guard lock(mutex_);
      error_ = std::current_exception();
      result_ready_.notify_all();
      return;
    } catch (const std::exception&) {
      std::lock_guard lock(mutex_);
      error_ = std::make_exception_ptr(
          Error(segmenter_->describe() + ": " + util::exception_message(std::current_exception())));
      result_ready_.notify_all();
      return;
    } catch (...) {
      std::lock_guard lock(mutex_);
      error_ = std::make_exception_ptr(Error("segmenter: unknown error"));
      result_ready_.notify_all();
      return;
    }
    {
      std::lock_guard lock(mutex_);
      newest_ = std::move(result);
    }
    result_ready_.notify_all();
  }
}

}  // namespace lrd::segmentation
