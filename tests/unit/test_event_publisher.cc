// The event publisher: order, delivery off the caller's thread, the bound on queued frames, and
// a subscriber's error kept for the owner instead of ending the process.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "lrd/events/event_publisher.h"
#include "lrd/util/error.h"

namespace {

using lrd::events::EventPublisher;
using lrd::events::FrameTracked;

struct Recorder : lrd::events::Subscriber {
  std::vector<std::uint64_t> frames;
  std::vector<std::uint64_t> keyframes;
  std::thread::id thread;
  std::atomic<bool> block{false};
  void on_frame(const FrameTracked& e) override {
    while (block.load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    thread = std::this_thread::get_id();
    frames.push_back(e.frame_id);
  }
  void on_keyframe(const lrd::events::KeyframeInserted& e) override { keyframes.push_back(e.keyframe_id); }
};

FrameTracked frame(std::uint64_t id) {
  FrameTracked e;
  e.frame_id = id;
  return e;
}

TEST(EventPublisher, DeliversEveryEventInOrderOnItsOwnThread) {
  lrd::util::ThreadErrors errors;
  EventPublisher publisher(errors);
  auto a = std::make_shared<Recorder>();
  auto b = std::make_shared<Recorder>();
  publisher.subscribe(a);
  publisher.subscribe(b);
  for (std::uint64_t i = 0; i < 100; ++i) {
    publisher.publish(frame(i));
    if (i % 10 == 0) publisher.publish(lrd::events::KeyframeInserted{0, i / 10, i, 0.0, {}, 0});
  }
  publisher.shutdown();
  ASSERT_EQ(a->frames.size(), 100u);
  for (std::uint64_t i = 0; i < 100; ++i) EXPECT_EQ(a->frames[i], i);
  EXPECT_EQ(b->frames, a->frames);
  EXPECT_EQ(a->keyframes.size(), 10u);
  EXPECT_NE(a->thread, std::this_thread::get_id());
  EXPECT_EQ(publisher.stats().delivered, 110u);
  EXPECT_FALSE(errors.has_error());
}

TEST(EventPublisher, ASlowSubscriberNeverStallsThePublisher) {
  lrd::util::ThreadErrors errors;
  EventPublisher publisher(errors);
  auto slow = std::make_shared<Recorder>();
  slow->block = true;  // the subscriber does not return until released
  publisher.subscribe(slow);
  const auto t0 = std::chrono::steady_clock::now();
  for (std::uint64_t i = 0; i < 1000; ++i) publisher.publish(frame(i));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(seconds, 1.0);  // 1000 publishes while nothing is delivered
  slow->block = false;
  publisher.flush();
  EXPECT_EQ(slow->frames.size(), 1000u);  // unbounded by default: nothing dropped
  EXPECT_EQ(publisher.stats().dropped_frames, 0u);
}

TEST(EventPublisher, BoundedQueueDropsTheOldestFramesOnly) {
  lrd::util::ThreadErrors errors;
  EventPublisher publisher(errors, 5);
  auto slow = std::make_shared<Recorder>();
  slow->block = true;
  publisher.subscribe(slow);
  publisher.publish(frame(0));  // taken by the delivery thread, which then blocks in it
  while (publisher.stats().max_queued == 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  for (std::uint64_t i = 1; i <= 50; ++i) {
    publisher.publish(frame(i));
    if (i == 25) publisher.publish(lrd::events::KeyframeInserted{0, 7, 25, 0.0, {}, 0});
  }
  slow->block = false;
  publisher.shutdown();
  ASSERT_FALSE(slow->frames.empty());
  EXPECT_EQ(slow->frames.back(), 50u);                        // the newest survives
  EXPECT_LE(slow->frames.size(), 6u);                         // frame 0 plus at most 5 queued
  EXPECT_EQ(slow->keyframes, std::vector<std::uint64_t>{7});  // never dropped
  EXPECT_GE(publisher.stats().dropped_frames, 45u);
}

struct Thrower : lrd::events::Subscriber {
  void on_frame(const FrameTracked& e) override {
    if (e.frame_id == 3) throw lrd::Error("viewer: cannot draw frame 3");
  }
};

TEST(EventPublisher, ASubscribersErrorIsKeptNamingThePublisherThread) {
  lrd::util::ThreadErrors errors;
  EventPublisher publisher(errors);
  publisher.subscribe(std::make_shared<Thrower>());
  for (std::uint64_t i = 0; i < 10; ++i) publisher.publish(frame(i));
  publisher.flush();  // returns: delivery stopped at the error
  publisher.shutdown();
  ASSERT_TRUE(errors.has_error());
  EXPECT_EQ(errors.message(), "publisher thread: viewer: cannot draw frame 3");
  EXPECT_THROW(errors.rethrow(), lrd::Error);
}

TEST(EventPublisher, SubscribersComeBeforeTheFirstEvent) {
  lrd::util::ThreadErrors errors;
  EventPublisher publisher(errors);
  publisher.subscribe(std::make_shared<Recorder>());
  publisher.publish(frame(0));
  EXPECT_THROW(publisher.subscribe(std::make_shared<Recorder>()), lrd::Error);
}

TEST(ThreadErrors, KeepsTheFirstErrorOnly) {
  lrd::util::ThreadErrors errors;
  EXPECT_NO_THROW(errors.rethrow());
  try {
    throw std::runtime_error("disk full");
  } catch (...) {
    errors.capture("dense mapping");
  }
  try {
    throw std::runtime_error("later");
  } catch (...) {
    errors.capture("local mapping");
  }
  EXPECT_EQ(errors.message(), "dense mapping thread: disk full");
}

}  // namespace
