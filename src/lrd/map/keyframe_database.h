#pragma once
// The inverse index of place recognition (ORB-SLAM2's KeyFrameDatabase, after DBoW2): for each
// vocabulary word the keyframes whose images contain it. A query scores only the keyframes that
// share words with it, so finding candidates costs little even with thousands of keyframes.
//
// Candidates are judged as groups (ORB-SLAM2): a keyframe's score is accumulated over its 10 most
// covisible neighbours, so one lucky view does not beat a place seen consistently, and the best
// keyframe of each strong group is returned.
//
// Call under Map::mutex(): keyframes' covisibility and bad flags are read. A keyframe removed
// from the map must be erased here before it can be freed (local mapping, which indexes
// keyframes, erases those it culls).
#include <cstdint>
#include <vector>

#include "lrd/place/bow_vector.h"

namespace lrd::data {
class Frame;
}
namespace lrd::map {

class KeyFrame;

class KeyFrameDatabase {
 public:
  // Indexes a keyframe (its BoW must be computed).
  void add(map::KeyFrame* kf);
  // Drops a keyframe (removed from the map) from the index.
  void erase(map::KeyFrame* kf);
  void clear();
  [[nodiscard]] std::size_t size() const { return keyframe_count_; }

  // Loop candidates for `kf`: older keyframes sharing no map point with it, with a score of at
  // least `min_score` and in a group scoring at least 75 % of the best group.
  [[nodiscard]] std::vector<map::KeyFrame*> loop_candidates(map::KeyFrame* kf, double min_score);
  // Relocalization candidates for a frame whose BoW is computed (tracking lost).
  [[nodiscard]] std::vector<map::KeyFrame*> relocalization_candidates(const data::Frame& frame);

 private:
  // Keyframes sharing at least 80 % of the best count of shared words, with their scores
  // (`exclude`: skipped; `min_score`: floor).
  std::vector<map::KeyFrame*> candidates(const place::BowVector& bow, std::uint64_t query,
                                         const std::vector<map::KeyFrame*>& exclude, double min_score);

  std::vector<std::vector<map::KeyFrame*>> inverted_;  // word -> keyframes, in insertion order
  std::size_t keyframe_count_ = 0;
  std::uint64_t next_query_ = 0;
};

}  // namespace lrd::map
