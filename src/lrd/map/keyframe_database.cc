#include "lrd/map/keyframe_database.h"

#include <algorithm>
#include <limits>

#include "lrd/data/frame.h"
#include "lrd/map/keyframe.h"
#include "lrd/place/vocabulary.h"

namespace lrd::map {

namespace {
constexpr double kSharedWordsRatio = 0.8;  // ORB-SLAM2: candidates share >= 80 % of the best count
constexpr double kGroupScoreRatio = 0.75;  // ... and their group scores >= 75 % of the best group
constexpr std::size_t kGroupSize = 10;     // a group: the keyframe and its 10 best covisibles
}  // namespace

void KeyFrameDatabase::add(map::KeyFrame* kf) {
  for (const auto& [word, weight] : kf->bow()) {
    if (word >= inverted_.size()) inverted_.resize(word + 1);
    inverted_[word].push_back(kf);
  }
  ++keyframe_count_;
}

void KeyFrameDatabase::erase(map::KeyFrame* kf) {
  bool found = false;
  for (const auto& [word, weight] : kf->bow()) {
    if (word >= inverted_.size()) continue;
    auto& list = inverted_[word];
    const auto it = std::find(list.begin(), list.end(), kf);
    if (it == list.end()) continue;
    list.erase(it);
    found = true;
  }
  if (found) --keyframe_count_;
}

void KeyFrameDatabase::clear() {
  inverted_.clear();
  keyframe_count_ = 0;
}

std::vector<map::KeyFrame*> KeyFrameDatabase::candidates(const place::BowVector& bow, std::uint64_t query,
                                                         const std::vector<map::KeyFrame*>& exclude,
                                                         double min_score) {
  // Excluded keyframes are marked as seen with a count that can never qualify.
  for (map::KeyFrame* kf : exclude) {
    kf->place_query_for = query;
    kf->place_shared_words = std::numeric_limits<int>::min() / 2;
    kf->place_score = -1.0;
  }
  std::vector<map::KeyFrame*> sharing;
  for (const auto& [word, weight] : bow) {
    if (word >= inverted_.size()) continue;
    for (map::KeyFrame* kf : inverted_[word]) {
      if (kf->is_bad()) continue;
      if (kf->place_query_for != query) {
        kf->place_query_for = query;
        kf->place_shared_words = 0;
        kf->place_score = -1.0;
        sharing.push_back(kf);
      }
      ++kf->place_shared_words;
    }
  }
  if (sharing.empty()) return {};
  int max_shared = 0;
  for (const map::KeyFrame* kf : sharing) max_shared = std::max(max_shared, kf->place_shared_words);
  const auto min_shared = static_cast<int>(kSharedWordsRatio * max_shared);
  std::sort(sharing.begin(), sharing.end(), map::ById{});
  std::vector<map::KeyFrame*> scored;
  for (map::KeyFrame* kf : sharing) {
    if (kf->place_shared_words < min_shared) continue;
    const double s = place::Vocabulary::score(bow, kf->bow());
    if (s < min_score) continue;
    kf->place_score = s;
    scored.push_back(kf);
  }
  if (scored.empty()) return {};

  // Group scores: each candidate with those of its best covisibles that also scored.
  struct Group {
    double score;
    map::KeyFrame* best;
  };
  std::vector<Group> groups;
  double best_group = 0.0;
  for (map::KeyFrame* kf : scored) {
    Group g{kf->place_score, kf};
    for (map::KeyFrame* n : kf->best_covisibles(kGroupSize)) {
      if (n->place_query_for != query || n->place_score < 0.0) continue;
      g.score += n->place_score;
      if (n->place_score > g.best->place_score) g.best = n;
    }
    best_group = std::max(best_group, g.score);
    groups.push_back(g);
  }
  std::stable_sort(groups.begin(), groups.end(),
                   [](const Group& a, const Group& b) { return a.score > b.score; });
  std::vector<map::KeyFrame*> out;
  for (const Group& g : groups) {
    if (g.score < kGroupScoreRatio * best_group) break;
    if (std::find(out.begin(), out.end(), g.best) == out.end()) out.push_back(g.best);
  }
  return out;
}

std::vector<map::KeyFrame*> KeyFrameDatabase::loop_candidates(map::KeyFrame* kf, double min_score) {
  // Every keyframe sharing a point with it, weak links included (ORB-SLAM2's connected
  // keyframes): the recent past is not a loop.
  std::vector<map::KeyFrame*> exclude = kf->connected_keyframes();
  exclude.push_back(kf);
  auto out = candidates(kf->bow(), next_query_++, exclude, min_score);
  // Keyframes indexed after it (threaded: local mapping runs ahead of loop closing) neither.
  out.erase(
      std::remove_if(out.begin(), out.end(), [&](const map::KeyFrame* c) { return c->id() >= kf->id(); }),
      out.end());
  return out;
}

std::vector<map::KeyFrame*> KeyFrameDatabase::relocalization_candidates(const data::Frame& frame) {
  return candidates(frame.bow, next_query_++, {}, 0.0);
}

}  // namespace lrd::map
