#include "lrd/events/event_publisher.h"

#include <algorithm>
#include <chrono>

#include "lrd/util/error.h"
#include "lrd/util/thread_priority.h"

namespace lrd::events {

EventPublisher::EventPublisher(util::ThreadErrors& errors, std::size_t max_queued_frames)
    : errors_(errors), max_queued_frames_(max_queued_frames) {}

EventPublisher::~EventPublisher() {
  shutdown();
}

void EventPublisher::subscribe(std::shared_ptr<Subscriber> subscriber) {
  std::lock_guard lock(mutex_);
  if (started_ || sealed_.load())
    throw Error("subscribe: subscribers must be registered before the first frame");
  if (subscriber) subscribers_.push_back(std::move(subscriber));
}

void EventPublisher::publish(Event event) {
  seal();
  if (subscribers_.empty()) return;
  {
    std::lock_guard lock(mutex_);
    if (stop_ || failed_) return;
    if (!started_) {
      started_ = true;
      thread_ = std::thread([this] { run(); });
    }
    queue_.push_back(std::move(event));
    ++stats_.published;
    if (max_queued_frames_ > 0) {
      const auto is_frame = [](const Event& e) { return std::holds_alternative<FrameTracked>(e); };
      while (static_cast<std::size_t>(std::count_if(queue_.begin(), queue_.end(), is_frame)) >
             max_queued_frames_) {
        queue_.erase(std::find_if(queue_.begin(), queue_.end(), is_frame));
        ++stats_.dropped_frames;
      }
    }
    stats_.max_queued = std::max(stats_.max_queued, queue_.size());
  }
  ready_.notify_one();
}

void EventPublisher::run() {
  util::name_this_thread("lrd-events");
  // Subscribers work below tracking's priority (as the dense thread): on a busy machine the
  // deliveries wait, the camera does not.
  util::lower_this_thread_priority();
  std::unique_lock lock(mutex_);
  for (;;) {
    ready_.wait(lock, [this] { return stop_ || !queue_.empty(); });
    if (queue_.empty()) break;  // stop requested and everything delivered
    Event event = std::move(queue_.front());
    queue_.pop_front();
    busy_ = true;
    lock.unlock();
    const auto t0 = std::chrono::steady_clock::now();
    bool ok = true;
    try {
      deliver(event);
    } catch (...) {
      errors_.capture("publisher");
      ok = false;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    lock.lock();
    busy_ = false;
    stats_.delivery_seconds += seconds;
    if (ok) ++stats_.delivered;
    if (!ok) {
      failed_ = true;
      queue_.clear();
    }
    if (queue_.empty()) drained_.notify_all();
    if (failed_) break;
  }
  drained_.notify_all();
}

void EventPublisher::deliver(const Event& event) {
  for (const auto& s : subscribers_) {
    std::visit(
        [&s](const auto& e) {
          using T = std::decay_t<decltype(e)>;
          if constexpr (std::is_same_v<T, FrameTracked>)
            s->on_frame(e);
          else if constexpr (std::is_same_v<T, KeyframeInserted>)
            s->on_keyframe(e);
          else if constexpr (std::is_same_v<T, LoopClosed>)
            s->on_loop(e);
          else if constexpr (std::is_same_v<T, MapChanged>)
            s->on_map_changed(e);
          else
            s->on_dense_map(e);
        },
        event);
  }
}

void EventPublisher::flush() {
  std::unique_lock lock(mutex_);
  if (!started_) return;
  drained_.wait(lock, [this] { return failed_ || (queue_.empty() && !busy_); });
}

void EventPublisher::shutdown() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  ready_.notify_all();
  if (thread_.joinable()) thread_.join();
}

PublisherStats EventPublisher::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace lrd::events
