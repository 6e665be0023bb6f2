#pragma once
// The local map a tracked frame is refined against (ORB-SLAM2's UpdateLocalMap and
// SearchLocalPoints, paper §2.2): the keyframes sharing map points with the frame, some of their
// neighbours, and the points those keyframes observe, projected into the frame to find more
// matches than the motion model's. Owned by the Tracker; used with the map mutex held.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "lrd/data/frame.h"
#include "lrd/match/orb_matcher.h"

namespace lrd::map {
class KeyFrame;
class MapPoint;
}  // namespace lrd::map

namespace lrd::tracking {

class LocalMap {
 public:
  LocalMap();

  // The keyframes and points around `frame`, tagged with the search pass `tag`: at most
  // `max_keyframes` keyframes. Returns the keyframe sharing the most points with the frame (its
  // new reference keyframe), or null when none shares any (the keyframes then stay as they were).
  map::KeyFrame* update(data::Frame& frame, std::uint64_t tag, std::size_t max_keyframes);
  // Projects the local points the frame has not matched yet into it and matches them within
  // `radius` px (at level 0); returns the matches found.
  int search(data::Frame& frame, std::uint64_t tag, float radius);
  // The map's first keyframe and all its points (the map has just been started).
  void start(map::KeyFrame* first, std::vector<map::MapPoint*> points);
  // Forgets keyframes and points the map has removed.
  void drop_removed();

  // What a search leaves, kept to undo a second search of the same frame.
  struct Contents {
    std::vector<map::KeyFrame*> keyframes;
    std::vector<map::MapPoint*> points;
  };
  [[nodiscard]] Contents contents() const { return {keyframes_, points_}; }
  void restore(Contents contents);

  [[nodiscard]] const std::vector<map::KeyFrame*>& keyframes() const { return keyframes_; }
  [[nodiscard]] const std::vector<map::MapPoint*>& points() const { return points_; }
  // The matcher the local points are searched with (relocalization's guided search uses it too).
  [[nodiscard]] const match::OrbMatcher& matcher() const { return matcher_; }

 private:
  map::KeyFrame* update_keyframes(data::Frame& frame, std::uint64_t tag, std::size_t max_keyframes);
  void update_points(std::uint64_t tag);

  match::OrbMatcher matcher_;  // nn 0.8, no rotation check
  std::vector<map::KeyFrame*> keyframes_;
  std::vector<map::MapPoint*> points_;
  std::uint64_t sharing_count_pass_ = 0;  // tags KeyFrame::track_shared_points
  std::vector<map::KeyFrame*> sharing_;   // update_keyframes' scratch list: no allocation per frame
};

}  // namespace lrd::tracking
