#include "lrd/synth/rasterizer.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lrd::synth {
namespace {
constexpr float kNear = 0.05f;  // metres; closer geometry is clipped
}

RenderBuffers RenderBuffers::clone() const {
  return {color.clone(), depth.clone(), voc_class.clone(), label.clone(), incidence.clone()};
}

Rasterizer::Rasterizer(const camera::PinholeCamera& camera, const TextureLibrary& textures, Lighting lighting)
    : cam_(camera), textures_(textures), lighting_(lighting) {}

RenderBuffers Rasterizer::make_buffers() const {
  const cv::Size s(cam_.width, cam_.height);
  return {cv::Mat(s, CV_8UC3, cv::Scalar(40, 40, 40)),
          cv::Mat(s, CV_32F, cv::Scalar(std::numeric_limits<float>::infinity())), cv::Mat::zeros(s, CV_8U),
          cv::Mat::zeros(s, CV_8U), cv::Mat::zeros(s, CV_32F)};
}

void Rasterizer::finish(RenderBuffers& buf) {
  buf.depth.setTo(0.0f, buf.depth == std::numeric_limits<float>::infinity());
}

void Rasterizer::draw(const std::vector<Triangle>& tris, const Eigen::Isometry3f& T_wc,
                      RenderBuffers& buf) const {
  const Eigen::Isometry3f T_cw = T_wc.inverse();
  const Eigen::Matrix3f R_cw = T_cw.linear();
  const Eigen::Vector3f cam_center = T_wc.translation();
  for (const Triangle& tri : tris) {
    // Back-face culling in world coordinates: the camera must be on the front side.
    if (tri.normal.dot(cam_center - tri.p[0]) <= 0.0f) continue;
    ClipVertex in[3];
    int n_front = 0;
    for (int i = 0; i < 3; ++i) {
      in[i].p = T_cw * tri.p[i];
      in[i].uv = tri.uv[i];
      n_front += in[i].p.z() > kNear;
    }
    if (n_front == 0) continue;
    // Lambert shading at the centroid with distance falloff (flat per triangle).
    const Eigen::Vector3f centroid = (tri.p[0] + tri.p[1] + tri.p[2]) / 3.0f;
    const Eigen::Vector3f to_light = lighting_.light_position - centroid;
    const float dist = to_light.norm();
    const float lambert = std::max(0.0f, tri.normal.dot(to_light) / dist);
    const float atten =
        1.0f / (1.0f + (dist / lighting_.falloff_distance) * (dist / lighting_.falloff_distance));
    const float shade = tri.albedo * (lighting_.ambient + lighting_.diffuse * lambert * (0.5f + atten));
    const Eigen::Vector3f n_c = R_cw * tri.normal;
    if (n_front == 3) {
      draw_triangle(in, tri, shade, n_c, buf);
      continue;
    }
    // Sutherland-Hodgman against the near plane; the polygon has at most 4 vertices.
    ClipVertex poly[4];
    int m = 0;
    for (int i = 0; i < 3; ++i) {
      const ClipVertex& a = in[i];
      const ClipVertex& b = in[(i + 1) % 3];
      const bool a_in = a.p.z() > kNear, b_in = b.p.z() > kNear;
      if (a_in) poly[m++] = a;
      if (a_in != b_in) {
        const float t = (kNear - a.p.z()) / (b.p.z() - a.p.z());
        poly[m++] = {a.p + t * (b.p - a.p), a.uv + t * (b.uv - a.uv)};
      }
    }
    for (int k = 1; k + 1 < m; ++k) {
      const ClipVertex fan[3] = {poly[0], poly[k], poly[k + 1]};
      draw_triangle(fan, tri, shade, n_c, buf);
    }
  }
}

void Rasterizer::draw_triangle(const ClipVertex* v, const Triangle& tri, float shade,
                               const Eigen::Vector3f& n_c, RenderBuffers& buf) const {
  const float fx = static_cast<float>(cam_.fx), fy = static_cast<float>(cam_.fy);
  const float cx = static_cast<float>(cam_.cx), cy = static_cast<float>(cam_.cy);
  float sx[3], sy[3], iz[3], uz[3], vz[3];
  for (int i = 0; i < 3; ++i) {
    iz[i] = 1.0f / v[i].p.z();
    sx[i] = fx * v[i].p.x() * iz[i] + cx;
    sy[i] = fy * v[i].p.y() * iz[i] + cy;
    uz[i] = v[i].uv.x() * iz[i];
    vz[i] = v[i].uv.y() * iz[i];
  }
  const float area = (sx[1] - sx[0]) * (sy[2] - sy[0]) - (sx[2] - sx[0]) * (sy[1] - sy[0]);
  if (std::abs(area) < 1e-6f) return;
  const int x_min = std::max(0, static_cast<int>(std::ceil(std::min({sx[0], sx[1], sx[2]}))));
  const int x_max = std::min(cam_.width - 1, static_cast<int>(std::floor(std::max({sx[0], sx[1], sx[2]}))));
  const int y_min = std::max(0, static_cast<int>(std::ceil(std::min({sy[0], sy[1], sy[2]}))));
  const int y_max = std::min(cam_.height - 1, static_cast<int>(std::floor(std::max({sy[0], sy[1], sy[2]}))));
  if (x_min > x_max || y_min > y_max) return;

  // Mip level from the texel-to-pixel area ratio of this triangle.
  const Texture& tex = textures_.get(tri.texture);
  const float du1 = v[1].uv.x() - v[0].uv.x(), dv1 = v[1].uv.y() - v[0].uv.y();
  const float du2 = v[2].uv.x() - v[0].uv.x(), dv2 = v[2].uv.y() - v[0].uv.y();
  const float texel_area = std::abs(du1 * dv2 - du2 * dv1) * static_cast<float>(tex.width() * tex.height());
  const float ratio = texel_area / std::abs(area);
  const int level = std::clamp(static_cast<int>(std::floor(0.5f * std::log2(std::max(ratio, 1.0f)) + 0.3f)),
                               0, tex.levels() - 1);

  // Edge functions w_i(x, y) = A_i x + B_i y + C_i, oriented so that inside is >= 0.
  const float sign = area > 0 ? 1.0f : -1.0f;
  float A[3], B[3], C[3];
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    A[i] = sign * (sy[j] - sy[k]);
    B[i] = sign * (sx[k] - sx[j]);
    C[i] = sign * (sx[j] * sy[k] - sx[k] * sy[j]);
  }
  const float inv_area = 1.0f / std::abs(area);
  // Attribute planes: attr(x, y) = (sum_i w_i attr_i) / |area|.
  auto plane = [&](const float* a, float& ax, float& ay, float& a0) {
    ax = (A[0] * a[0] + A[1] * a[1] + A[2] * a[2]) * inv_area;
    ay = (B[0] * a[0] + B[1] * a[1] + B[2] * a[2]) * inv_area;
    a0 = (C[0] * a[0] + C[1] * a[1] + C[2] * a[2]) * inv_area;
  };
  float izx, izy, iz0, uzx, uzy, uz0, vzx, vzy, vz0;
  plane(iz, izx, izy, iz0);
  plane(uz, uzx, uzy, uz0);
  plane(vz, vzx, vzy, vz0);

  const auto label = static_cast<std::uint8_t>(tri.label);
  const float inv_fx = 1.0f / fx, inv_fy = 1.0f / fy;
  for (int y = y_min; y <= y_max; ++y) {
    const float yf = static_cast<float>(y);
    // The covered span of this row, from the three half-planes A x + (B y + C) >= 0. Shared edges
    // give bit-identical bounds in both triangles (their A, B, C are exact negations): no cracks.
    int lo = x_min, hi = x_max;
    bool empty = false;
    for (int i = 0; i < 3 && !empty; ++i) {
      const float r0 = B[i] * yf + C[i];
      if (A[i] > 0.0f) {
        lo = std::max(lo, static_cast<int>(std::ceil(-r0 / A[i])));
      } else if (A[i] < 0.0f) {
        hi = std::min(hi, static_cast<int>(std::floor(-r0 / A[i])));
      } else if (r0 < 0.0f) {
        empty = true;
      }
    }
    if (empty || lo > hi) continue;
    auto* color = buf.color.ptr<cv::Vec3b>(y);
    auto* depth = buf.depth.ptr<float>(y);
    auto* cls = buf.voc_class.ptr<std::uint8_t>(y);
    auto* lab = buf.label.ptr<std::uint8_t>(y);
    auto* inc = buf.incidence.ptr<float>(y);
    const float ry = (yf - cy) * inv_fy;
    const float ndot_y = n_c.y() * ry + n_c.z();
    const float ry2 = ry * ry + 1.0f;
    float inv_z = izx * static_cast<float>(lo) + izy * yf + iz0;
    float u_z = uzx * static_cast<float>(lo) + uzy * yf + uz0;
    float v_z = vzx * static_cast<float>(lo) + vzy * yf + vz0;
    for (int x = lo; x <= hi; ++x, inv_z += izx, u_z += uzx, v_z += vzx) {
      if (inv_z <= 0.0f) continue;
      const float z = 1.0f / inv_z;
      if (z >= depth[x]) continue;
      float rgb[3];
      tex.sample(level, u_z * z, v_z * z, rgb);
      color[x] = cv::Vec3b(cv::saturate_cast<uchar>(rgb[0] * shade), cv::saturate_cast<uchar>(rgb[1] * shade),
                           cv::saturate_cast<uchar>(rgb[2] * shade));
      depth[x] = z;
      cls[x] = tri.voc_class;
      lab[x] = label;
      const float rx = (static_cast<float>(x) - cx) * inv_fx;
      inc[x] = std::abs(n_c.x() * rx + ndot_y) / std::sqrt(rx * rx + ry2);
    }
  }
}

}  // namespace lrd::synth
