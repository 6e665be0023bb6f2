#pragma once
// The node's frames between the image callback and the tracking thread: bounded, the oldest frame
// dropped (and counted) when a new one arrives at a full queue, so a camera faster than tracking
// never makes the callback wait or the memory grow; the tracker always gets the newest frames.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>

namespace lrd::node {

template <typename Frame>
class FrameQueue {
 public:
  explicit FrameQueue(std::size_t capacity) : capacity_(capacity < 1 ? 1 : capacity) {}

  // Never blocks. Returns false (and drops nothing) after close().
  bool push(Frame frame) {
    {
      std::lock_guard lock(mutex_);
      if (closed_) return false;
      if (queue_.size() >= capacity_) {
        queue_.pop_front();
        ++dropped_;
      }
      queue_.push_back(std::move(frame));
    }
    ready_.notify_one();
    return true;
  }

  // Blocks for the next frame; nullopt once closed and empty.
  std::optional<Frame> pop() {
    std::unique_lock lock(mutex_);
    ready_.wait(lock, [this] { return closed_ || !queue_.empty(); });
    if (queue_.empty()) return std::nullopt;
    Frame f = std::move(queue_.front());
    queue_.pop_front();
    return f;
  }

  // No more frames: pop() returns what is queued, then nullopt.
  void close() {
    {
      std::lock_guard lock(mutex_);
      closed_ = true;
    }
    ready_.notify_all();
  }

  [[nodiscard]] std::size_t dropped() const {
    std::lock_guard lock(mutex_);
    return dropped_;
  }

 private:
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<Frame> queue_;
  std::size_t dropped_ = 0;
  bool closed_ = false;
};

}  // namespace lrd::node
