#pragma once
// The 256 point-pair tests of the steered BRIEF descriptor (Calonder et al. 2010, steered as in
// Rublee et al. 2011, "ORB: an efficient alternative to SIFT or SURF").
#include <array>
#include <cstdint>

namespace lrd::features {

// One binary test: bit = I(p1) < I(p2), offsets in pixels from the keypoint before rotation.
struct BriefPair {
  std::int8_t x1, y1, x2, y2;
};

// Every offset lies within this radius, so a pattern rotated by any angle stays inside it.
inline constexpr int kBriefRadius = 13;

// The fixed pattern, learned as Rublee et al. learn rBRIEF (sec. 4.3): tests whose bits are
// closest to even on oriented keypoints, greedily kept only while weakly correlated with those
// already kept. Regenerate with bench/learn_brief_pattern.cc.
[[nodiscard]] const std::array<BriefPair, 256>& brief_pattern();

}  // namespace lrd::features
