#pragma once
// The hand-off between a producer thread and a background worker (local mapping, loop closing):
// a FIFO with a condition variable and a stop request. A threaded worker blocks in wait_pop();
// a lock-step worker (deterministic runs) drains it with try_pop() in the caller's thread.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>

namespace lrd::util {

template <class T>
class WorkQueue {
 public:
  void push(T item) {
    {
      std::lock_guard lock(mutex_);
      items_.push_back(std::move(item));
    }
    cv_.notify_one();
  }

  [[nodiscard]] std::optional<T> try_pop() {
    std::lock_guard lock(mutex_);
    return pop_locked();
  }

  // Blocks until an item arrives or stop() was called; after stop(), what is queued still comes
  // out, then nullopt. `on_pop` runs under the queue's lock with each item taken, so that a
  // "busy" flag set there is never seen false while the queue looks empty.
  template <class OnPop>
  [[nodiscard]] std::optional<T> wait_pop(OnPop&& on_pop) {
    std::unique_lock lock(mutex_);
    cv_.wait(lock, [this] { return stopped_ || !items_.empty(); });
    auto item = pop_locked();
    if (item) on_pop();
    return item;
  }
  [[nodiscard]] std::optional<T> wait_pop() {
    return wait_pop([] {});
  }

  // Lock-step: takes every queued item through `process` in the calling thread. Once `process`
  // has thrown, does nothing more (the caller has the error; the rest of the queue stays).
  template <class Process>
  void drain(Process&& process) {
    if (drain_failed_) return;
    try {
      while (auto item = try_pop()) process(std::move(*item));
    } catch (...) {
      drain_failed_ = true;
      throw;
    }
  }

  void stop() {
    {
      std::lock_guard lock(mutex_);
      stopped_ = true;
    }
    cv_.notify_all();
  }

  [[nodiscard]] std::size_t size() const {
    std::lock_guard lock(mutex_);
    return items_.size();
  }

 private:
  std::optional<T> pop_locked() {
    if (items_.empty()) return std::nullopt;
    T item = std::move(items_.front());
    items_.pop_front();
    return item;
  }

  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<T> items_;
  bool stopped_ = false;
  bool drain_failed_ = false;  // the draining thread's only
};

}  // namespace lrd::util
