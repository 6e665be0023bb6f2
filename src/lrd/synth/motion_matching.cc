#include "lrd/synth/motion_matching.h"

#include <cmath>
#include <functional>
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

// The x in [0, hi] where `f` (increasing in x) reaches `goal`: bisection, a fixed number of steps
// so that the result is the same on every run.
double solve_increasing(const std::function<double(double)>& f, double goal, double hi) {
  double lo = 0.0;
  while (f(hi) < goal && hi < 64.0) hi *= 2.0;
  for (int step = 0; step < 40; ++step) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) < goal ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

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
  HandHeldMotion h;
  const auto speed = [&](const HandHeldMotion& m) {
    return statistics_with(smooth, m, duration, fps).mean_speed;
  };
  const auto turn = [&](const HandHeldMotion& m) {
    return statistics_with(smooth, m, duration, fps).mean_angular_speed;
  };
  // Translation first: the 1-s displacement's length does not depend on the rotation.
  if (speed(h) > target.mean_speed) {
    h.path_scale = solve_increasing(
        [&](double s) {
          HandHeldMotion m = h;
          m.path_scale = s;
          return speed(m);
        },
        target.mean_speed, 1.0);
  } else {
    h.translation_sway = solve_increasing(
        [&](double a) {
          HandHeldMotion m = h;
          m.translation_sway = a;
          return speed(m);
        },
        target.mean_speed, 0.1);
  }
  if (turn(h) < target.mean_angular_speed) {
    h.rotation_sway = solve_increasing(
        [&](double a) {
          HandHeldMotion m = h;
          m.rotation_sway = a;
          return turn(m);
        },
        target.mean_angular_speed, 0.1);
  }
  return h;
}

}  // namespace lrd::synth
