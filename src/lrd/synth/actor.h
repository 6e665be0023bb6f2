#pragma once
// A moving thing in the synthetic scene. Its geometry at time t is a pure function of t, so any
// frame can be rendered independently (and in parallel) with identical results.
#include <string>

#include "lrd/synth/triangle_soup.h"

namespace lrd::synth {

class Actor {
 public:
  virtual ~Actor() = default;
  // Appends the actor's world-space triangles at time t (seconds from the sequence start).
  virtual void add_geometry(double t, TriangleSoup& soup) const = 0;
  [[nodiscard]] virtual std::string describe() const = 0;
};

}  // namespace lrd::synth
