#include "lrd/synth/motion_matching.h"

#include <cmath>
#include <map>

#include "lrd/eval/motion_statistics.h"

namespace lrd::synth {
namespace {

// TUM's statistics of the hand-held motion `h` applied to `smooth`.
eval::MotionStatistics statistics_with(const CameraMotion& smooth, const HandHeldMotion& h, double duration,
                                       double fps) {
  CameraMotion camera = smooth;
  camera.set_hand_held(h);
  io::Trajectory trajectory;
  const int n = static_cast<int>(std::lround(duration * fps));
  trajectory.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double t = i / fps;
    trajectory.push_back({t, camera.pose_at(t)});
  }
  return eval::motion_statistics(trajectory);
}

using Statistic = double eval::MotionStatistics::*;
using Amplitude = double HandHeldMotion::*;

// The hand-held motion's amplitudes solved for one at a time on one smooth path.
struct Matcher {
  const CameraMotion& smooth;
  double duration, fps;

  [[nodiscard]] double measure(const HandHeldMotion& h, Statistic statistic) const {
    return statistics_with(smooth, h, duration, fps).*statistic;
  }
  // The value of `amplitude` in [0, hi] (hi doubled while too small) at which `statistic`,
  // increasing in it, reaches `goal`: bisection, a fixed number of steps so that the result is the
  // same on every run.
  [[nodiscard]] double solve(HandHeldMotion h, Amplitude amplitude, Statistic statistic, double goal,
                             double hi) const {
    const auto f = [&](double x) {
      h.*amplitude = x;
      return measure(h, statistic);
    };
    double lo = 0.0;
    while (f(hi) < goal && hi < 64.0) hi *= 2.0;
    for (int step = 0; step < 40; ++step) {
      const double mid = 0.5 * (lo + hi);
      (f(mid) < goal ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }
};

}  // namespace

std::optional<MotionTarget> tum_fr3_motion(const std::string& preset) {
  // "Avg. translational velocity" and "avg. angular velocity" of each fr3 sequence on the TUM RGB-D
  // dataset page (docs/synthetic-benchmark.md quotes them with their durations and lengths).
  static const std::map<std::string, MotionTarget> published = {
      {"walking_xyz", {0.208, 5.49}},         {"walking_static", {0.012, 1.39}},
      {"walking_halfsphere", {0.221, 18.27}}, {"walking_rpy", {0.091, 20.90}},
      {"sitting_xyz", {0.132, 3.56}},         {"sitting_halfsphere", {0.180, 19.09}},
      {"sitting_static", {0.011, 1.70}},
  };
  const auto it = published.find(preset);
  if (it == published.end()) return std::nullopt;
  return it->second;
}

HandHeldMotion match_motion(const CameraMotion& smooth, const MotionTarget& target, double duration,
                            double fps) {
  const Matcher matcher{smooth, duration, fps};
  constexpr Statistic speed = &eval::MotionStatistics::mean_speed;
  constexpr Statistic turn = &eval::MotionStatistics::mean_angular_speed;
  HandHeldMotion h;
  // Translation first: the 1-s displacement's length does not depend on the rotation.
  if (matcher.measure(h, speed) > target.mean_speed)
    h.path_scale = matcher.solve(h, &HandHeldMotion::path_scale, speed, target.mean_speed, 1.0);
  else
    h.translation_sway = matcher.solve(h, &HandHeldMotion::translation_sway, speed, target.mean_speed, 0.1);
  if (matcher.measure(h, turn) < target.mean_angular_speed)
    h.rotation_sway = matcher.solve(h, &HandHeldMotion::rotation_sway, turn, target.mean_angular_speed, 0.1);
  return h;
}

}  // namespace lrd::synth
