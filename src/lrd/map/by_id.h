#pragma once
// Orders map objects by their id rather than their address, so that every container of
// keyframes or map points iterates in the same order on every run (deterministic mode).
namespace lrd::map {

struct ById {
  template <class T>
  bool operator()(const T* a, const T* b) const {
    return a->id() < b->id();
  }
};

}  // namespace lrd::map
