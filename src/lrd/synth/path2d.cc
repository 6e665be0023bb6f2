#include "lrd/synth/path2d.h"

#include <algorithm>
#include <cmath>

#include "lrd/util/error.h"

namespace lrd::synth {

ClosedPath::ClosedPath(const std::vector<Eigen::Vector2f>& w, int samples_per_segment) {
  if (w.size() < 2) throw Error("synth: a path needs at least two waypoints");
  const std::size_t n = w.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2f& p0 = w[(i + n - 1) % n];
    const Eigen::Vector2f& p1 = w[i];
    const Eigen::Vector2f& p2 = w[(i + 1) % n];
    const Eigen::Vector2f& p3 = w[(i + 2) % n];
    for (int k = 0; k < samples_per_segment; ++k) {
      const float t = static_cast<float>(k) / static_cast<float>(samples_per_segment);
      const float t2 = t * t, t3 = t2 * t;
      points_.push_back(0.5f * ((2.0f * p1) + (-p0 + p2) * t + (2.0f * p0 - 5.0f * p1 + 4.0f * p2 - p3) * t2 +
                                (-p0 + 3.0f * p1 - 3.0f * p2 + p3) * t3));
    }
  }
  points_.push_back(points_.front());
  cumulative_.push_back(0.0f);
  for (std::size_t i = 1; i < points_.size(); ++i)
    cumulative_.push_back(cumulative_.back() + (points_[i] - points_[i - 1]).norm());
}

Eigen::Vector2f ClosedPath::point_at(float s) const {
  const float L = length();
  s = std::fmod(s, L);
  if (s < 0) s += L;
  const auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), s);
  const std::size_t i =
      std::clamp<std::size_t>(static_cast<std::size_t>(it - cumulative_.begin()), 1, points_.size() - 1);
  const float seg = cumulative_[i] - cumulative_[i - 1];
  const float a = seg > 0 ? (s - cumulative_[i - 1]) / seg : 0.0f;
  return points_[i - 1] + a * (points_[i] - points_[i - 1]);
}

void ClosedPath::at(float s, Eigen::Vector2f& position, Eigen::Vector2f& heading) const {
  position = point_at(s);
  // Heading from points 0.15 m ahead and behind, so turns look like turns, not kinks.
  heading = point_at(s + 0.15f) - point_at(s - 0.15f);
  const float n = heading.norm();
  heading = n > 1e-6f ? Eigen::Vector2f(heading / n) : Eigen::Vector2f(1, 0);
}

}  // namespace lrd::synth
