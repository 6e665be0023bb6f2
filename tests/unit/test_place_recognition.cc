// Place recognition end to end on rendered synthetic sequences, with the shipped vocabulary:
// tracking lost over a blanked stretch relocalizes within 10 frames of the view returning, in the
// same map; a camera circling the room closes the loop where it started.
#include <gtest/gtest.h>

#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "lrd/eval/ate.h"
#include "lrd/synth/synthetic_sequence.h"
#include "lrd/system.h"

namespace {

struct Sequence {
  lrd::camera::PinholeCamera camera;
  std::vector<lrd::synth::SynthFrame> frames;  // blanked frames: black, no depth (not rendered)
  lrd::io::Trajectory ground_truth;
};

// Every `stride`-th frame of a preset (a faster camera), `count` of them; frames with index in
// [blank_from, blank_to) are blank.
Sequence render(const std::string& preset, int stride, int count, int blank_from = -1, int blank_to = -1) {
  lrd::synth::SynthOptions o;
  o.preset = preset;
  o.seed = 3;
  const lrd::synth::SyntheticSequence s(o);
  Sequence r;
  r.camera = s.camera();
  for (int k = 0; k < count; ++k) {
    const int i = k * stride;
    lrd::synth::SynthFrame f;
    if (k >= blank_from && k < blank_to) {
      f.index = i;
      f.timestamp = s.timestamp(i);
      f.pose = s.pose(i);
      f.rgb = cv::Mat::zeros(r.camera.height, r.camera.width, CV_8UC3);
      f.depth = cv::Mat::zeros(r.camera.height, r.camera.width, CV_16UC1);
    } else {
      f = s.render(i);
    }
    r.ground_truth.push_back({f.timestamp, f.pose});
    r.frames.push_back(std::move(f));
  }
  return r;
}

struct RunResult {
  std::vector<lrd::TrackingState> states;
  lrd::io::Trajectory trajectory;
  std::vector<lrd::loop::LoopEvent> loops;
  std::vector<lrd::loop::GlobalBaRun> global_ba_runs;
  std::vector<lrd::TrackResult> results;
  lrd::MapStats map;
};

RunResult run(const Sequence& seq, bool loop_closing) {
  lrd::config::Config c;
  c.camera = seq.camera;
  lrd::SystemOptions options;
  options.deterministic = true;
  options.loop_closing = loop_closing;
  lrd::System slam(c, options);
  EXPECT_FALSE(slam.vocabulary_file().empty()) << "the shipped vocabulary was not found";
  RunResult r;
  cv::Mat rgb;
  for (const auto& f : seq.frames) {
    cv::cvtColor(f.rgb, rgb, cv::COLOR_BGR2RGB);
    r.results.push_back(slam.track_rgbd(rgb, f.depth, f.timestamp));
    r.states.push_back(r.results.back().state);
  }
  slam.shutdown();
  r.trajectory = slam.trajectory();
  r.loops = slam.loops();
  r.global_ba_runs = slam.global_ba_runs();
  r.map = slam.map_stats();
  return r;
}

TEST(PlaceRecognition, RelocalizesWithinTenFramesOfTheViewReturning) {
  // The camera sweeps on while the lens is covered for 60 frames (2 s): when the view returns,
  // the motion model is useless and only place recognition can find the pose.
  constexpr int kBlankFrom = 40, kBlankTo = 100;
  const Sequence seq = render("static_xyz", 1, 130, kBlankFrom, kBlankTo);
  const RunResult r = run(seq, true);
  for (int i = 5; i < kBlankFrom; ++i)
    EXPECT_EQ(r.states[static_cast<std::size_t>(i)], lrd::TrackingState::Ok) << i;
  for (int i = kBlankFrom; i < kBlankTo; ++i)
    EXPECT_EQ(r.states[static_cast<std::size_t>(i)], lrd::TrackingState::Lost) << i;
  int back = -1;
  for (int i = kBlankTo; i < static_cast<int>(r.states.size()); ++i)
    if (r.states[static_cast<std::size_t>(i)] == lrd::TrackingState::Ok) {
      back = i;
      break;
    }
  ASSERT_GE(back, kBlankTo) << "never relocalized";
  EXPECT_LE(back, kBlankTo + 10);
  EXPECT_GE(r.map.relocalizations, 1);
  // The local map each frame was tracked against (bench_scale's figure): none while lost.
  for (std::size_t i = 5; i < r.results.size(); ++i) {
    const lrd::TrackResult& t = r.results[i];
    if (t.state == lrd::TrackingState::Ok) {
      EXPECT_GE(t.local_keyframes, 1u) << i;
      EXPECT_GE(t.local_points, static_cast<std::size_t>(t.inliers)) << i;
    } else {
      EXPECT_EQ(t.local_keyframes, 0u) << i;
      EXPECT_EQ(t.local_points, 0u) << i;
    }
  }
  // Same map: one alignment fits the trajectory before and after the gap.
  const auto ate = lrd::eval::compute_ate(seq.ground_truth, r.trajectory);
  EXPECT_LT(ate.stats.rmse, 0.02);
  EXPECT_GE(r.trajectory.size(), 60u);
}

TEST(PlaceRecognition, ClosesTheLoopWhereTheCameraReturns) {
  // static_loop at every 4th frame: a 0.6 m circle in 125 frames, then 55 more past the start
  // (the loop is confirmed once 3 consecutive keyframes agree: around frame 150).
  const Sequence seq = render("static_loop", 4, 180);
  const RunResult with = run(seq, true);
  ASSERT_GE(with.loops.size(), 1u);
  // Deterministic mode stays bit-identical with a loop closure and global BA in the run.
  const RunResult again = run(seq, true);
  ASSERT_EQ(again.trajectory.size(), with.trajectory.size());
  for (std::size_t i = 0; i < with.trajectory.size(); ++i)
    ASSERT_TRUE(again.trajectory[i].pose.matrix() == with.trajectory[i].pose.matrix()) << i;
  const auto& loop = with.loops.front();
  EXPECT_GE(loop.inliers, 40);
  // The two keyframes really are the same place: the ground-truth camera positions of the
  // closing frame and of the matched keyframe's frame are close.
  EXPECT_GT(loop.frame_id, 100u);  // after most of the lap
  EXPECT_LT(loop.frame_id, 180u);
  EXPECT_LT(loop.loop_keyframe_id, 10u);  // back at the start
  // Its size and latency (bench_scale, bench/results/scale.md): the keyframes then in the map (ids
  // from 0, some culled), at least a spanning tree of edges, and the one global BA that followed
  // it.
  EXPECT_GT(loop.keyframes, 10u);
  EXPECT_LE(loop.keyframes, loop.keyframe_id + 1);
  EXPECT_GE(loop.pose_graph_edges, loop.keyframes - 1);
  EXPECT_GT(loop.detection_seconds, 0.0);
  EXPECT_GT(loop.correction_seconds, 0.0);
  ASSERT_EQ(with.global_ba_runs.size(), 1u);
  const auto& ba = with.global_ba_runs.front();
  EXPECT_EQ(ba.loop_keyframe_id, loop.keyframe_id);
  EXPECT_GE(static_cast<std::size_t>(ba.keyframes), loop.keyframes);
  EXPECT_GT(ba.points, 1000);
  EXPECT_GT(ba.seconds, 0.0);
  EXPECT_FALSE(ba.aborted);
  const auto ate_with = lrd::eval::compute_ate(seq.ground_truth, with.trajectory);
  const RunResult without = run(seq, false);
  EXPECT_TRUE(without.loops.empty());
  const auto ate_without = lrd::eval::compute_ate(seq.ground_truth, without.trajectory);
  std::printf("ATE with loop closing %.2f cm, without %.2f cm\n", 100 * ate_with.stats.rmse,
              100 * ate_without.stats.rmse);
  EXPECT_LT(ate_with.stats.rmse, 0.6 * ate_without.stats.rmse);
  EXPECT_LT(ate_with.stats.rmse, 0.015);
}

}  // namespace
