#include "lrd/match/bow_matcher.h"

#include <functional>
#include <limits>

#include "lrd/data/frame.h"
#include "lrd/features/descriptor_distance.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/map_point.h"
#include "lrd/match/rotation_histogram.h"

namespace lrd::match {

namespace {

struct Pair {
  std::size_t a = SIZE_MAX;  // keypoint in view a
  int distance = std::numeric_limits<int>::max();
};

// For each keypoint b of view `b` accepted by `use_b`, the best keypoint of view `a` (accepted by
// `use_a`) under the same vocabulary node, if it passes the distance and ratio tests; a keypoint
// of `a` goes to at most one of `b` (the closer one).
std::vector<Pair> match_nodes(const data::Frame& a, const std::function<bool(std::size_t)>& use_a,
                              const data::Frame& b, const std::function<bool(std::size_t)>& use_b,
                              const MatcherParams& params) {
  std::vector<Pair> for_b(b.size());
  std::vector<int> best_for_a(a.size(), std::numeric_limits<int>::max());
  std::vector<std::size_t> chosen_b(a.size(), SIZE_MAX);
  auto ia = a.bow_features.begin();
  auto ib = b.bow_features.begin();
  // Both maps are ordered by node: walk them together.
  while (ia != a.bow_features.end() && ib != b.bow_features.end()) {
    if (ia->first < ib->first) {
      ia = a.bow_features.lower_bound(ib->first);
      continue;
    }
    if (ib->first < ia->first) {
      ib = b.bow_features.lower_bound(ia->first);
      continue;
    }
    for (const std::uint32_t i : ia->second) {
      if (!use_a(i)) continue;
      const std::uint8_t* da = a.descriptors().ptr(static_cast<int>(i));
      int best = 256, second = 256;
      std::size_t best_j = SIZE_MAX;
      for (const std::uint32_t j : ib->second) {
        if (!use_b(j)) continue;
        const int d = features::descriptor_distance(da, b.descriptors().ptr(static_cast<int>(j)));
        if (d < best) {
          second = best;
          best = d;
          best_j = j;
        } else if (d < second) {
          second = d;
        }
      }
      if (best_j == SIZE_MAX || best > OrbMatcher::kThLow ||
          static_cast<float>(best) >= params.nn_ratio * static_cast<float>(second))
        continue;
      if (best < for_b[best_j].distance && best < best_for_a[i]) {
        if (for_b[best_j].a != SIZE_MAX)
          chosen_b[for_b[best_j].a] = SIZE_MAX, best_for_a[for_b[best_j].a] = 256;
        if (chosen_b[i] != SIZE_MAX) for_b[chosen_b[i]] = Pair{};
        for_b[best_j] = {i, best};
        best_for_a[i] = best;
        chosen_b[i] = best_j;
      }
    }
    ++ia;
    ++ib;
  }
  if (params.check_orientation) {
    RotationHistogram hist;
    for (std::size_t j = 0; j < for_b.size(); ++j)
      if (for_b[j].a != SIZE_MAX) hist.add(a.undistorted()[for_b[j].a].angle, b.undistorted()[j].angle, j);
    for (const std::size_t j : hist.rejected()) for_b[j] = Pair{};
  }
  return for_b;
}

bool good(const map::MapPoint* mp) {
  return mp != nullptr && !mp->is_bad();
}

// The source keyframe's map points matched to the target view's keypoints accepted by
// `use_target`: out[target keypoint] = map point.
int match_points(const map::KeyFrame& source, const data::Frame& target,
                 const std::function<bool(std::size_t)>& use_target, const MatcherParams& params,
                 std::vector<map::MapPoint*>& out) {
  out.assign(target.size(), nullptr);
  const auto pairs = match_nodes(
      source.features(), [&](std::size_t i) { return good(source.map_point(i)); }, target, use_target,
      params);
  int n = 0;
  for (std::size_t j = 0; j < pairs.size(); ++j) {
    if (pairs[j].a == SIZE_MAX) continue;
    out[j] = source.map_point(pairs[j].a);
    ++n;
  }
  return n;
}

}  // namespace

int BowMatcher::match(const map::KeyFrame& kf, const data::Frame& frame,
                      std::vector<map::MapPoint*>& out) const {
  return match_points(
      kf, frame, [](std::size_t) { return true; }, params_, out);
}

int BowMatcher::match(const map::KeyFrame& kf1, const map::KeyFrame& kf2,
                      std::vector<map::MapPoint*>& out) const {
  return match_points(
      kf2, kf1.features(), [&](std::size_t j) { return good(kf1.map_point(j)); }, params_, out);
}

}  // namespace lrd::match
