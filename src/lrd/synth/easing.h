#pragma once
// Easing of the actors' scripted motions: a start and an end at rest, no jerk in between.
#include <algorithm>

namespace lrd::synth {

// 0 at x <= 0, 1 at x >= 1, zero slope at both ends.
inline float smoothstep(double x) {
  const auto s = static_cast<float>(std::clamp(x, 0.0, 1.0));
  return s * s * (3.0f - 2.0f * s);
}

}  // namespace lrd::synth
