#pragma once
// Delivers the system's events to any number of subscribers without ever stalling tracking:
// publish() only queues the event; the publisher's own thread (at the lowest priority, nice 19)
// hands each event, in order, to every subscriber. Subscribers are registered before the first event. A
// subscriber that throws stops the delivery; the error is kept (util::ThreadErrors, thread "publisher") and
// the system rethrows it.
//
// The queue is unbounded by default (the CLI runner needs every frame); with max_queued_frames
// set, the oldest queued FrameTracked events are dropped past it (a live viewer wants the newest
// frame, not a backlog) and counted. Other events are never dropped.
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>
#include <variant>
#include <vector>

#include "lrd/events/events.h"
#include "lrd/util/thread_errors.h"

namespace lrd::events {

// Override what you need; each call runs on the publisher's thread, one at a time.
class Subscriber {
 public:
  virtual ~Subscriber() = default;
  virtual void on_frame(const FrameTracked& /*event*/) {}
  virtual void on_keyframe(const KeyframeInserted& /*event*/) {}
  virtual void on_loop(const LoopClosed& /*event*/) {}
  virtual void on_map_changed(const MapChanged& /*event*/) {}
  virtual void on_dense_map(const DenseMapUpdated& /*event*/) {}
};

using Event = std::variant<FrameTracked, KeyframeInserted, LoopClosed, MapChanged, DenseMapUpdated>;

struct PublisherStats {
  std::size_t published = 0;
  std::size_t delivered = 0;
  std::size_t dropped_frames = 0;
  std::size_t max_queued = 0;
  double delivery_seconds = 0.0;  // subscribers' time, on the publisher's thread
};

class EventPublisher {
 public:
  explicit EventPublisher(util::ThreadErrors& errors, std::size_t max_queued_frames = 0);
  ~EventPublisher();
  EventPublisher(const EventPublisher&) = delete;
  EventPublisher& operator=(const EventPublisher&) = delete;

  // Before seal() (System seals at its first frame) and the first publish(); throws lrd::Error
  // after.
  void subscribe(std::shared_ptr<Subscriber> subscriber);
  // No more subscribers from now on: from here, the list is read without a lock by any thread.
  void seal() { sealed_.store(true); }
  [[nodiscard]] bool has_subscribers() const { return sealed_.load() && !subscribers_.empty(); }
  // A subscriber threw: delivery has stopped for good.
  [[nodiscard]] bool failed() const {
    std::lock_guard lock(mutex_);
    return failed_;
  }
  // Any thread. Does nothing without subscribers.
  void publish(Event event);
  // Waits until everything published so far is delivered (or delivery stopped on an error).
  void flush();
  // Delivers what is queued and stops the thread. Idempotent.
  void shutdown();
  [[nodiscard]] PublisherStats stats() const;

 private:
  void run();
  void deliver(const Event& event);

  util::ThreadErrors& errors_;
  const std::size_t max_queued_frames_;
  std::vector<std::shared_ptr<Subscriber>> subscribers_;
  std::atomic<bool> sealed_{false};
  mutable std::mutex mutex_;
  std::condition_variable ready_, drained_;
  std::deque<Event> queue_;
  bool started_ = false, stop_ = false, busy_ = false, failed_ = false;
  PublisherStats stats_;
  std::thread thread_;
};

}  // namespace lrd::events
