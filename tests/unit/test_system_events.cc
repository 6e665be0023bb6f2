// lrd::System's publishers and lifecycle on a short static sequence rendered in memory: one frame
// event per frame with the pose track_rgbd returned, keyframe and map events that agree with the
// map, snapshots, reset() to a new map, and a subscriber's error ending the run with an error
// that names the thread.
#include <gtest/gtest.h>

#include <mutex>
#include <opencv2/imgproc.hpp>
#include <set>
#include <string>

#include "lrd/synth/synthetic_sequence.h"
#include "lrd/system.h"
#include "lrd/util/error.h"
#include "rendered_sequence.h"

namespace {

const lrd::test::RenderedSequence& frames() {
  return lrd::test::static_sequence();
}

lrd::config::Config config() {
  return lrd::test::config_for(frames().camera);
}

struct Watcher : lrd::events::Subscriber {
  std::mutex mutex;
  std::vector<lrd::events::FrameTracked> frame_events;
  std::vector<lrd::events::KeyframeInserted> keyframe_events;
  std::vector<lrd::events::MapChanged> map_events;
  void on_frame(const lrd::events::FrameTracked& e) override {
    std::lock_guard lock(mutex);
    frame_events.push_back(e);
  }
  void on_keyframe(const lrd::events::KeyframeInserted& e) override { keyframe_events.push_back(e); }
  void on_map_changed(const lrd::events::MapChanged& e) override { map_events.push_back(e); }
};

TEST(SystemEvents, OneFrameEventPerFrameWithThePoseTrackingReturned) {
  lrd::SystemOptions options;
  options.deterministic = true;
  lrd::System slam(config(), options);
  auto watcher = std::make_shared<Watcher>();
  slam.subscribe(watcher);
  std::vector<lrd::TrackResult> results;
  for (const auto& f : frames().frames) results.push_back(slam.track_rgbd(f.rgb, f.depth, f.timestamp));
  const lrd::events::MapSnapshot snapshot = slam.map_snapshot();
  slam.shutdown();

  ASSERT_EQ(watcher->frame_events.size(), results.size());
  std::size_t keyframe_frames = 0;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const auto& e = watcher->frame_events[i];
    EXPECT_EQ(e.frame_id, i);
    EXPECT_EQ(e.timestamp, frames().frames[i].timestamp);
    EXPECT_EQ(e.state, results[i].state);
    ASSERT_TRUE(results[i].T_wc.has_value()) << "frame " << i;  // a static scene: every frame tracked
    ASSERT_TRUE(e.T_wc.has_value());
    EXPECT_TRUE(e.T_wc->isApprox(*results[i].T_wc, 1e-12));
    EXPECT_EQ(e.inliers, results[i].inliers);
    EXPECT_EQ(e.grey.type(), CV_8UC1);
    EXPECT_EQ(e.kept_keypoints.size(), static_cast<std::size_t>(results[i].dynamic.keypoints));
    keyframe_frames += e.new_keyframe.has_value();
  }
  EXPECT_EQ(results.front().state, lrd::TrackingState::Ok);
  // Every keyframe made has its event, in order, and the map holds those not culled.
  ASSERT_EQ(watcher->keyframe_events.size(), keyframe_frames);
  ASSERT_GE(watcher->keyframe_events.size(), 2u);
  EXPECT_EQ(watcher->keyframe_events.front().frame_id, 0u);
  std::set<std::uint64_t> made;
  for (const auto& k : watcher->keyframe_events) made.insert(k.keyframe_id);
  EXPECT_EQ(made.size(), watcher->keyframe_events.size());
  ASSERT_FALSE(snapshot.keyframes.empty());
  for (const auto& k : snapshot.keyframes) EXPECT_TRUE(made.count(k.keyframe_id)) << k.keyframe_id;
  // Local mapping reported each processed keyframe; the last report matches the final map.
  ASSERT_FALSE(watcher->map_events.empty());
  EXPECT_EQ(watcher->map_events.back().keyframes, slam.map_stats().keyframes);
  // The snapshot's points are observed by snapshot keyframes.
  ASSERT_GT(snapshot.points.size(), 100u);
  for (const auto& p : snapshot.points) {
    ASSERT_FALSE(p.keyframes.empty());
    EXPECT_TRUE(made.count(p.keyframes.front()));
  }
  EXPECT_EQ(slam.publisher_stats().dropped_frames, 0u);
}

TEST(SystemEvents, SubscribersComeBeforeTheFirstFrame) {
  lrd::System slam(config());
  slam.subscribe(std::make_shared<Watcher>());
  const auto& f = frames().frames.front();
  (void)slam.track_rgbd(f.rgb, f.depth, f.timestamp);
  EXPECT_THROW(slam.subscribe(std::make_shared<Watcher>()), lrd::Error);
}

TEST(SystemEvents, ResetStartsANewMapInTheSameProcess) {
  lrd::SystemOptions options;
  options.deterministic = true;
  lrd::System slam(config(), options);
  const auto& f = frames().frames;
  for (std::size_t i = 0; i < 20; ++i) (void)slam.track_rgbd(f[i].rgb, f[i].depth, f[i].timestamp);
  ASSERT_EQ(slam.trajectory().size(), 20u);
  slam.reset();
  EXPECT_EQ(slam.state(), lrd::TrackingState::NotInitialized);
  EXPECT_TRUE(slam.trajectory().empty());
  EXPECT_EQ(slam.map_stats().keyframes, 0u);
  // The new map starts at frame 20: its first keyframe is the world origin there.
  const lrd::TrackResult first = slam.track_rgbd(f[20].rgb, f[20].depth, f[20].timestamp);
  ASSERT_EQ(first.state, lrd::TrackingState::Ok);
  EXPECT_TRUE(first.T_wc->isApprox(Eigen::Isometry3d::Identity(), 1e-12));
  for (std::size_t i = 21; i < f.size(); ++i) {
    const lrd::TrackResult r = slam.track_rgbd(f[i].rgb, f[i].depth, f[i].timestamp);
    ASSERT_EQ(r.state, lrd::TrackingState::Ok) << "frame " << i;
  }
  slam.shutdown();
  EXPECT_EQ(slam.trajectory().size(), f.size() - 20);
  EXPECT_GE(slam.map_stats().keyframes, 1u);
}

struct FailingViewer : lrd::events::Subscriber {
  void on_frame(const lrd::events::FrameTracked& e) override {
    if (e.frame_id == 2) throw lrd::Error("viewer.png: cannot write");
  }
};

TEST(SystemEvents, AThreadsErrorEndsTheRunWithAnErrorNamingTheThread) {
  lrd::System slam(config());  // threaded
  slam.subscribe(std::make_shared<FailingViewer>());
  const auto& f = frames().frames;
  std::string message;
  try {
    // Delivery is asynchronous: the error surfaces at a later track_rgbd or at shutdown.
    for (std::size_t i = 0; i < f.size(); ++i) (void)slam.track_rgbd(f[i].rgb, f[i].depth, f[i].timestamp);
    slam.shutdown();
  } catch (const lrd::Error& e) {
    message = e.what();
  }
  EXPECT_EQ(message, "publisher thread: viewer.png: cannot write");
  // Shutting down after the error stops every thread and reports the same error, never another.
  std::string again = message;
  try {
    slam.shutdown();
  } catch (const lrd::Error& e) {
    again = e.what();
  }
  EXPECT_EQ(again, message);
}

}  // namespace
