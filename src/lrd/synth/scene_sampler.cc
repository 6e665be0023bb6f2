#include "lrd/synth/scene_sampler.h"

#include <algorithm>
#include <cmath>

#include "lrd/synth/portable_random.h"

namespace lrd::synth {

dense::PointCloud sample_surfaces(const TriangleSoup& soup, const TextureLibrary& textures, double spacing,
                                  std::uint64_t seed) {
  dense::PointCloud out;
  PortableRandom rng(seed);
  const double per_m2 = 1.0 / (spacing * spacing);
  double carry = 0.0;  // fractional samples carried to the next triangle, so small ones still count
  for (const Triangle& t : soup.triangles()) {
    if (t.label != MaskLabel::kStatic) continue;
    const Eigen::Vector3f e1 = t.p[1] - t.p[0], e2 = t.p[2] - t.p[0];
    const double area = 0.5 * static_cast<double>(e1.cross(e2).norm());
    carry += area * per_m2;
    const auto n = static_cast<int>(std::floor(carry));
    carry -= n;
    const Texture& tex = textures.get(t.texture);
    for (int k = 0; k < n; ++k) {
      float a = rng.uniform(0.0f, 1.0f), b = rng.uniform(0.0f, 1.0f);
      if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;  // fold the square onto the triangle
      out.points.push_back(t.p[0] + a * e1 + b * e2);
      const Eigen::Vector2f uv = t.uv[0] + a * (t.uv[1] - t.uv[0]) + b * (t.uv[2] - t.uv[0]);
      float bgr[3];
      tex.sample(std::min(2, tex.levels() - 1), uv.x(), uv.y(), bgr);
      const auto c = [&](float v) {
        return static_cast<unsigned char>(std::clamp(v * t.albedo, 0.0f, 255.0f));
      };
      out.colours.emplace_back(c(bgr[0]), c(bgr[1]), c(bgr[2]));
    }
  }
  return out;
}

}  // namespace lrd::synth
