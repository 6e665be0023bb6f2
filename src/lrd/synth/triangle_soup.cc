#include "lrd/synth/triangle_soup.h"

#include <cmath>

namespace lrd::synth {

void TriangleSoup::add_triangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                                const Eigen::Vector2f& ta, const Eigen::Vector2f& tb,
                                const Eigen::Vector2f& tc, const SurfaceStyle& style) {
  Triangle t;
  t.p[0] = a;
  t.p[1] = b;
  t.p[2] = c;
  t.uv[0] = ta;
  t.uv[1] = tb;
  t.uv[2] = tc;
  const Eigen::Vector3f n = (b - a).cross(c - a);
  const float len = n.norm();
  if (len < 1e-12f) return;  // degenerate: nothing to draw
  t.normal = n / len;
  t.texture = style.texture;
  t.albedo = style.albedo;
  t.voc_class = style.voc_class;
  t.label = style.label;
  tris_.push_back(t);
}

void TriangleSoup::add_quad(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                            const Eigen::Vector3f& d, const Eigen::Vector2f& ta, const Eigen::Vector2f& tb,
                            const Eigen::Vector2f& tc, const Eigen::Vector2f& td, const SurfaceStyle& style) {
  add_triangle(a, b, c, ta, tb, tc, style);
  add_triangle(a, c, d, ta, tc, td, style);
}

void TriangleSoup::add_plane(const Eigen::Vector3f& origin, const Eigen::Vector3f& u,
                             const Eigen::Vector3f& v, const SurfaceStyle& style, float tile, bool stretch) {
  const float lu = u.norm(), lv = v.norm();
  const int nu = std::max(1, static_cast<int>(std::ceil(lu / tile)));
  const int nv = std::max(1, static_cast<int>(std::ceil(lv / tile)));
  auto tex = [&](float su, float sv) -> Eigen::Vector2f {
    // Image rows grow downwards while v grows upwards on walls: flip v so photos stand upright.
    if (stretch) return {su, 1.0f - sv};
    return {su * lu / style.metres_per_repeat, (1.0f - sv) * lv / style.metres_per_repeat};
  };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const float s0 = static_cast<float>(i) / nu, s1 = static_cast<float>(i + 1) / nu;
      const float t0 = static_cast<float>(j) / nv, t1 = static_cast<float>(j + 1) / nv;
      add_quad(origin + s0 * u + t0 * v, origin + s1 * u + t0 * v, origin + s1 * u + t1 * v,
               origin + s0 * u + t1 * v, tex(s0, t0), tex(s1, t0), tex(s1, t1), tex(s0, t1), style);
    }
  }
}

void TriangleSoup::add_box(const Eigen::Isometry3f& pose, const Eigen::Vector3f& size,
                           const SurfaceStyle& style, const SurfaceStyle* top) {
  const Eigen::Vector3f h = 0.5f * size;
  const Eigen::Matrix3f R = pose.linear();
  const Eigen::Vector3f c = pose.translation();
  auto P = [&](float x, float y, float z) -> Eigen::Vector3f { return c + R * Eigen::Vector3f(x, y, z); };
  const float tile = 0.6f;
  // Each face: origin, u edge, v edge with u x v pointing outwards.
  add_plane(P(-h.x(), -h.y(), -h.z()), R * Eigen::Vector3f(size.x(), 0, 0),
            R * Eigen::Vector3f(0, 0, size.z()), style, tile);  // -y
  add_plane(P(h.x(), h.y(), -h.z()), R * Eigen::Vector3f(-size.x(), 0, 0),
            R * Eigen::Vector3f(0, 0, size.z()), style, tile);  // +y
  add_plane(P(h.x(), -h.y(), -h.z()), R * Eigen::Vector3f(0, size.y(), 0),
            R * Eigen::Vector3f(0, 0, size.z()), style, tile);  // +x
  add_plane(P(-h.x(), h.y(), -h.z()), R * Eigen::Vector3f(0, -size.y(), 0),
            R * Eigen::Vector3f(0, 0, size.z()), style, tile);  // -x
  add_plane(P(-h.x(), -h.y(), h.z()), R * Eigen::Vector3f(size.x(), 0, 0),
            R * Eigen::Vector3f(0, size.y(), 0), top ? *top : style, tile);  // +z
  add_plane(P(-h.x(), h.y(), -h.z()), R * Eigen::Vector3f(size.x(), 0, 0),
            R * Eigen::Vector3f(0, -size.y(), 0), style, tile);  // -z
}

void TriangleSoup::add_prism(const Eigen::Isometry3f& pose, float rx0, float ry0, float rx1, float ry1,
                             float length, int sides, const SurfaceStyle& style) {
  const Eigen::Matrix3f R = pose.linear();
  const Eigen::Vector3f c = pose.translation();
  auto ring = [&](int k, float rx, float ry, float z) -> Eigen::Vector3f {
    const float a = 2.0f * static_cast<float>(M_PI) * static_cast<float>(k) / static_cast<float>(sides);
    return c + R * Eigen::Vector3f(rx * std::cos(a), ry * std::sin(a), z);
  };
  const float circumference = static_cast<float>(M_PI) * (rx0 + ry0 + rx1 + ry1) * 0.5f;
  const float u_scale = circumference / style.metres_per_repeat, v_scale = length / style.metres_per_repeat;
  for (int k = 0; k < sides; ++k) {
    const float u0 = u_scale * static_cast<float>(k) / sides,
                u1 = u_scale * static_cast<float>(k + 1) / sides;
    add_quad(ring(k, rx0, ry0, 0), ring(k + 1, rx0, ry0, 0), ring(k + 1, rx1, ry1, length),
             ring(k, rx1, ry1, length), {u0, v_scale}, {u1, v_scale}, {u1, 0}, {u0, 0}, style);
  }
  const Eigen::Vector3f base = c, tip = c + R * Eigen::Vector3f(0, 0, length);
  for (int k = 0; k < sides; ++k) {
    const float a0 = 2.0f * static_cast<float>(M_PI) * k / sides,
                a1 = 2.0f * static_cast<float>(M_PI) * (k + 1) / sides;
    const Eigen::Vector2f t0(0.5f + 0.2f * std::cos(a0), 0.5f + 0.2f * std::sin(a0));
    const Eigen::Vector2f t1(0.5f + 0.2f * std::cos(a1), 0.5f + 0.2f * std::sin(a1));
    add_triangle(tip, ring(k, rx1, ry1, length), ring(k + 1, rx1, ry1, length), {0.5f, 0.5f}, t0, t1, style);
    add_triangle(base, ring(k + 1, rx0, ry0, 0), ring(k, rx0, ry0, 0), {0.5f, 0.5f}, t1, t0, style);
  }
}

}  // namespace lrd::synth
