#pragma once
// World-space textured triangles and the builders for the shapes the synthetic scene is made of
// (subdivided planes, boxes, tapered elliptic prisms for limbs).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "lrd/synth/texture_library.h"

namespace lrd::synth {

// What the ground-truth mask says of a surface (mask/*.png values): people; objects moved by
// people (a pushed chair, a carried box, while they move); a thrown balloon.
enum class MaskLabel : std::uint8_t { kStatic = 0, kPerson = 1, kMovedObject = 2, kBalloon = 3 };

// Pascal VOC class ids of the surfaces, so the renders can also serve as segmentation data.
namespace voc {
inline constexpr std::uint8_t kBackground = 0, kBottle = 5, kChair = 9, kDiningTable = 11, kPerson = 15,
                              kPottedPlant = 16, kSofa = 18, kTvMonitor = 20;
}

struct SurfaceStyle {
  TextureId texture = 0;
  float metres_per_repeat = 1.0f;  // texture tile size on the surface
  float albedo = 1.0f;
  std::uint8_t voc_class = voc::kBackground;
  MaskLabel label = MaskLabel::kStatic;
};

struct Triangle {
  Eigen::Vector3f p[3];    // world coordinates, counter-clockwise seen from the front
  Eigen::Vector2f uv[3];   // texture coordinates in repeats
  Eigen::Vector3f normal;  // unit, pointing to the front
  TextureId texture = 0;
  float albedo = 1.0f;
  std::uint8_t voc_class = 0;
  MaskLabel label = MaskLabel::kStatic;
};

class TriangleSoup {
 public:
  [[nodiscard]] const std::vector<Triangle>& triangles() const { return tris_; }
  [[nodiscard]] std::size_t size() const { return tris_.size(); }
  void clear() { tris_.clear(); }
  void append(const TriangleSoup& other) {
    tris_.insert(tris_.end(), other.tris_.begin(), other.tris_.end());
  }

  // Quad a-b-c-d (counter-clockwise seen from the front) with explicit texture coordinates.
  void add_quad(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                const Eigen::Vector3f& d, const Eigen::Vector2f& ta, const Eigen::Vector2f& tb,
                const Eigen::Vector2f& tc, const Eigen::Vector2f& td, const SurfaceStyle& style);

  // Plane from `origin` spanned by edges `u` and `v` (front = u x v), split into tiles of at most
  // `tile` metres so that per-triangle mip selection and near-plane clipping stay local.
  // Texture coordinates are metric (metres / style.metres_per_repeat) unless `stretch` maps the
  // whole plane onto one texture repeat (posters, screens).
  void add_plane(const Eigen::Vector3f& origin, const Eigen::Vector3f& u, const Eigen::Vector3f& v,
                 const SurfaceStyle& style, float tile = 0.5f, bool stretch = false);

  // Axis-aligned box (in `pose`'s frame) centred at `pose`'s origin with full extents `size`,
  // outward faces. `top` overrides the style of the +z face when given.
  void add_box(const Eigen::Isometry3f& pose, const Eigen::Vector3f& size, const SurfaceStyle& style,
               const SurfaceStyle* top = nullptr);

  // Tapered elliptic prism along `pose`'s +z from 0 to `length`: radii (rx0, ry0) at the base and
  // (rx1, ry1) at the tip, `sides` facets, capped. Used for limbs, torso, head.
  void add_prism(const Eigen::Isometry3f& pose, float rx0, float ry0, float rx1, float ry1, float length,
                 int sides, const SurfaceStyle& style);

 private:
  void add_triangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                    const Eigen::Vector2f& ta, const Eigen::Vector2f& tb, const Eigen::Vector2f& tc,
                    const SurfaceStyle& style);
  std::vector<Triangle> tris_;
};

}  // namespace lrd::synth
