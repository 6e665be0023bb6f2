#include "lrd/io/frame_prefetcher.h"

#include <algorithm>
#include <chrono>
#include <string>

#include "lrd/util/error.h"
#include "lrd/util/fault_injection.h"
#include "lrd/util/thread_priority.h"

namespace lrd::io {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::size_t checked_depth(const FrameSource& source, std::size_t depth) {
  if (depth == 0) throw file_error(source.path(), "frame prefetch queue depth must be >= 1");
  return depth;
}

}  // namespace

FramePrefetcher::FramePrefetcher(std::shared_ptr<const FrameSource> source, double depth_factor,
                                 PrefetchOptions options)
    : source_(std::move(source)),
      depth_factor_(depth_factor),
      queue_depth_(checked_depth(*source_, options.queue_depth)),
      begin_(std::min(options.begin, source_->size())),
      end_(std::clamp(options.end, begin_, source_->size())),
      thread_([this] { run(); }) {}

FramePrefetcher::~FramePrefetcher() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  not_full_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void FramePrefetcher::run() {
  util::name_this_thread("lrd-decode");
  for (std::size_t i = begin_; i < end_; ++i) {
    {
      std::unique_lock lock(mutex_);
      not_full_.wait(lock, [this] { return stop_ || queue_.size() < queue_depth_; });
      if (stop_) return;
    }
    // Decode outside the lock so the consumer can keep taking frames meanwhile.
    const auto t0 = Clock::now();
    std::optional<RgbdFrame> frame;
    std::exception_ptr error;
    try {
      if (i > begin_) util::check_fault_point("prefetcher");
      frame = source_->load_rgbd(i, depth_factor_);
    } catch (...) {
      error = std::current_exception();
    }
    const double dt = seconds_since(t0);
    {
      std::lock_guard lock(mutex_);
      stats_.decode_seconds += dt;
      if (error) {
        error_ = error;
        done_ = true;
      } else {
        ++stats_.frames;
        queue_.push_back(std::move(*frame));
      }
    }
    not_empty_.notify_one();
    if (error) return;
  }
  {
    std::lock_guard lock(mutex_);
    done_ = true;
  }
  not_empty_.notify_all();
}

std::optional<RgbdFrame> FramePrefetcher::next() {
  const auto t0 = Clock::now();
  std::unique_lock lock(mutex_);
  not_empty_.wait(lock, [this] { return !queue_.empty() || done_; });
  stats_.wait_seconds += seconds_since(t0);
  if (!queue_.empty()) {
    RgbdFrame frame = std::move(queue_.front());
    queue_.pop_front();
    lock.unlock();
    not_full_.notify_one();
    return frame;
  }
  if (error_) std::rethrow_exception(error_);
  return std::nullopt;
}

void FramePrefetcher::wait_until_decoded() {
  std::unique_lock lock(mutex_);
  not_empty_.wait(lock, [this] { return done_; });
}

DecodeStats FramePrefetcher::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace lrd::io
