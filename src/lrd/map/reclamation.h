#pragma once
// Deferred reclamation of culled keyframes and map points (quiescent-state-based reclamation).
//
// Keyframes and map points removed from the map (culled, fused away) cannot be freed at once:
// other threads may still hold pointers to them that they took before the removal — tracking's
// last frame, local BA solving without the map mutex, a running global BA. ORB-SLAM2 never frees
// them for that reason, so its memory grows with every point it ever created. Here each thread
// that keeps map pointers between two holds of the map mutex is a *participant*: it declares,
// now and then, a quiescent moment at which it holds no pointer to a removed object (it drops or
// replaces such pointers first). An object removed before every participant's latest quiescent
// moment can be reached by nobody and is freed.
//
// Removals and declarations happen with Map::mutex() held: a participant checks its pointers
// and declares in the same hold, so no removal can slip in between. Objects are freed only at a
// declaration or a departure, never at removal: code holding the map mutex (and tests) may still
// look at what it has just removed. join() and leave() may be called without the map mutex.
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace lrd::map {

class KeyFrame;
class MapPoint;

struct ReclamationStats {
  std::uint64_t freed_keyframes = 0;
  std::uint64_t freed_map_points = 0;
  std::size_t waiting_keyframes = 0;  // removed, not yet freed
  std::size_t waiting_map_points = 0;
};

class Reclamation {
 public:
  using Participant = std::size_t;

  Reclamation();
  ~Reclamation();
  Reclamation(const Reclamation&) = delete;
  Reclamation& operator=(const Reclamation&) = delete;

  // A thread that will keep map pointers between holds of the map mutex. From now on nothing
  // removed is freed before it declares (or leaves). A participant that left is not used again
  // (its number may be given to a later one).
  Participant join(std::string name);
  // It holds no map pointers any more (its owner shuts down).
  void leave(Participant p);
  // It holds no pointer to an object removed so far: frees what nobody can reach any more.
  void quiescent(Participant p);

  void retire(std::unique_ptr<KeyFrame> kf);
  void retire(std::unique_ptr<MapPoint> mp);

  [[nodiscard]] ReclamationStats stats() const;

 private:
  struct Member {
    std::string name;
    bool active = false;
    std::uint64_t seen = 0;  // epoch of its latest quiescent moment
  };
  template <class T>
  struct Retired {
    std::unique_ptr<T> object;
    std::uint64_t epoch;  // removed after every quiescent moment up to this epoch
  };
  void collect();  // with mutex_ held

  mutable std::mutex mutex_;
  // Each quiescent moment starts a new epoch; a removal is tagged with the epoch it happened in
  // and is safe once every active participant has declared in a later one.
  std::uint64_t epoch_ = 0;
  std::vector<Member> members_;
  std::deque<Retired<KeyFrame>> keyframes_;
  std::deque<Retired<MapPoint>> points_;
  ReclamationStats stats_;
};

// RAII membership for an object that owns a thread (leaves when destroyed).
class ReclamationMembership {
 public:
  ReclamationMembership(Reclamation& reclamation, std::string name)
      : reclamation_(&reclamation), id_(reclamation.join(std::move(name))) {}
  ~ReclamationMembership() { reclamation_->leave(id_); }
  ReclamationMembership(const ReclamationMembership&) = delete;
  ReclamationMembership& operator=(const ReclamationMembership&) = delete;
  void quiescent() { reclamation_->quiescent(id_); }

 private:
  Reclamation* reclamation_;
  Reclamation::Participant id_;
};

}  // namespace lrd::map
