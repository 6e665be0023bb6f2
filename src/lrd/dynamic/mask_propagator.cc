#include "lrd/dynamic/mask_propagator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "lrd/util/cpu_features.h"

namespace lrd::dynamic {

namespace {

// Half-widths of a disc's rows: row dv of the disc of `radius` spans |du| <= w[|dv|], the pixels
// with du^2 + dv^2 <= radius^2.
std::vector<int> disc_half_widths(int radius) {
  std::vector<int> w(static_cast<std::size_t>(radius) + 1);
  for (int dv = 0; dv <= radius; ++dv) {
    int u = 0;
    while ((u + 1) * (u + 1) + dv * dv <= radius * radius) ++u;
    w[static_cast<std::size_t>(dv)] = u;
  }
  return w;
}

// Index of the first nonzero byte of row[from, end), or end: whole zero words are skipped, since
// masks are mostly empty.
int next_set(const std::uint8_t* row, int from, int end) {
  int u = from;
  while (u < end && (u & 7) != 0 && row[u] == 0) ++u;
  while (u + 8 <= end) {
    std::uint64_t word;
    std::memcpy(&word, row + u, sizeof word);
    if (word != 0) break;
    u += 8;
  }
  while (u < end && row[u] == 0) ++u;
  return u;
}

// The 2x2 splat of propagate_mask at (x, y), clipped to the image.
void splat(cv::Mat& out, int x, int y) {
  if (x >= 0 && y >= 0 && x + 1 < out.cols && y + 1 < out.rows) {  // the common case
    auto* o = out.ptr<std::uint8_t>(y) + x;
    o[0] = o[1] = o[out.step[0]] = o[out.step[0] + 1] = 255;
    return;
  }
  if (x < -1 || y < -1 || x >= out.cols || y >= out.rows) return;
  for (int v = std::max(y, 0); v <= std::min(y + 1, out.rows - 1); ++v) {
    auto* o = out.ptr<std::uint8_t>(v);
    for (int u = std::max(x, 0); u <= std::min(x + 1, out.cols - 1); ++u) o[u] = 255;
  }
}

// Sets the blocks [x0, x1] x [y0, y1] of `half`, clipped to it.
void fill_blocks(cv::Mat& half, int x0, int x1, int y0, int y1) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0);
  x1 = std::min(x1, half.cols - 1), y1 = std::min(y1, half.rows - 1);
  if (x1 < x0) return;
  for (int y = y0; y <= y1; ++y)
    std::memset(half.ptr<std::uint8_t>(y) + x0, 255, static_cast<std::size_t>(x1 - x0 + 1));
}

// `out` (allocated, zeroed): `mask` grown by the disc of `radius`. Each run of set pixels is written,
// widened by the disc's half-width, into the 2r+1 rows the disc covers: the cost follows the masked
// area, not the disc's, where cv::dilate with an elliptic element grew with the radius (640x480:
// radius 7 0.46 ms, 11 1.0 ms, 31 ~15 ms).
void dilate_into(const cv::Mat& mask, int radius, cv::Mat& out) {
  const std::vector<int> w = disc_half_widths(radius);
  out = cv::Mat::zeros(mask.size(), CV_8UC1);
  for (int v = 0; v < mask.rows; ++v) {
    const auto* m = mask.ptr<std::uint8_t>(v);
    for (int u = next_set(m, 0, mask.cols); u < mask.cols; u = next_set(m, u, mask.cols)) {
      int end = u;
      while (end < mask.cols && m[end] != 0) ++end;
      for (int y = std::max(0, v - radius); y <= std::min(mask.rows - 1, v + radius); ++y) {
        const int half = w[static_cast<std::size_t>(std::abs(y - v))];
        const int a = std::max(0, u - half), b = std::min(mask.cols, end + half);
        std::memset(out.ptr<std::uint8_t>(y) + a, 255, static_cast<std::size_t>(b - a));
      }
      u = end;
    }
  }
}

// Pixel (x, y) of `out` (size `size`) takes block (x / 2, y / 2) of `half`: each byte doubled
// along the row (one 16-bit store), each row written twice.
void upsample_blocks(const cv::Mat& half, cv::Size size, cv::Mat& out) {
  out.create(size, CV_8UC1);
  const int pairs = size.width / 2;
  for (int y = 0; y < size.height; y += 2) {
    const auto* in = half.ptr<std::uint8_t>(y / 2);
    auto* row = out.ptr<std::uint8_t>(y);
    for (int x = 0; x < pairs; ++x) {
      const auto doubled = static_cast<std::uint16_t>(in[x] * 0x0101u);
      std::memcpy(row + 2 * x, &doubled, sizeof doubled);
    }
    if (size.width % 2 != 0) row[size.width - 1] = in[pairs];
    if (y + 1 < size.height)
      std::memcpy(out.ptr<std::uint8_t>(y + 1), row, static_cast<std::size_t>(size.width));
  }
}

// The motion of carry_mask in single precision: R row-major, t, the camera, the image's size.
struct BlockMotion {
  float r[9], t[3], fx, fy, cx, cy, width, height;
};

// Where row v's pixels land (x, y) when carried at their depths d, and whether in view (in front
// of the camera and within two pixels of the image); bx: the columns' bearings, by: the row's.
// Inlined into two copies below (baseline and AVX2): the same arithmetic, the same result.
[[gnu::always_inline]] inline void project_row(const float* d, const float* bx, float by, int begin, int end,
                                               const BlockMotion& m, float* xs, float* ys, int* seen) {
  // R (bx, by, 1) summed as Eigen sums a 3x3 product, r0 bx + (r1 by + r2): the same masks, bit
  // for bit, as an Eigen matrix-vector product per pixel (mask carry-over vectorised,
  // bench/results/performance.md).
  const float c0 = m.r[1] * by + m.r[2], c1 = m.r[4] * by + m.r[5], c2 = m.r[7] * by + m.r[8];
  for (int u = begin; u < end; ++u) {
    const float qx = (m.r[0] * bx[u] + c0) * d[u] + m.t[0];
    const float qy = (m.r[3] * bx[u] + c1) * d[u] + m.t[1];
    const float qz = (m.r[6] * bx[u] + c2) * d[u] + m.t[2];
    const float x = m.fx * qx / qz + m.cx, y = m.fy * qy / qz + m.cy;
    xs[u] = x, ys[u] = y;
    // int, not bool: a byte beside the floats keeps the loop from vectorising (GCC 12).
    seen[u] = (qz > 0.05f) & (x > -2.0f) & (y > -2.0f) & (x < m.width + 2.0f) & (y < m.height + 2.0f);
  }
}

void project_row_baseline(const float* d, const float* bx, float by, int begin, int end, const BlockMotion& m,
                          float* xs, float* ys, int* seen) {
  project_row(d, bx, by, begin, end, m, xs, ys, seen);
}

#ifdef LRD_AVX2_COPIES
[[gnu::target("avx2")]] void project_row_avx2(const float* d, const float* bx, float by, int begin, int end,
                                              const BlockMotion& m, float* xs, float* ys, int* seen) {
  project_row(d, bx, by, begin, end, m, xs, ys, seen);
}
#endif

// out[u] = a[u] | b[u], eight bytes at a time (the byte loop stays scalar: the rows may alias).
void either_row(const std::uint8_t* a, const std::uint8_t* b, int n, std::uint8_t* out) {
  int u = 0;
  for (; u + 8 <= n; u += 8) {
    std::uint64_t x, y;
    std::memcpy(&x, a + u, sizeof x);
    std::memcpy(&y, b + u, sizeof y);
    x |= y;
    std::memcpy(out + u, &x, sizeof x);
  }
  for (; u < n; ++u) out[u] = a[u] | b[u];
}

// carry_mask's half-resolution step: each 2x2 block of `mask` with a masked pixel moves as one,
// with its first masked pixel that has depth; a block with masked pixels without depth also stays
// where it was, as those pixels do in propagate_mask. Sets blocks of `half` (zeroed by the caller).
void carry_blocks(const cv::Mat& mask, const cv::Mat& depth, const BlockMotion& motion, cv::Mat& half) {
  const bool has_depth = !depth.empty() && depth.type() == CV_32FC1 && depth.size() == mask.size();
  const auto cols = static_cast<std::size_t>(mask.cols);
  std::vector<float> bearing_x(cols), no_depth(has_depth ? 0 : cols, 0.0f);
  for (int u = 0; u < mask.cols; ++u)
    bearing_x[static_cast<std::size_t>(u)] = (static_cast<float>(u) - motion.cx) / motion.fx;
  std::vector<float> xs[2] = {std::vector<float>(cols), std::vector<float>(cols)};
  std::vector<float> ys[2] = {std::vector<float>(cols), std::vector<float>(cols)};
  std::vector<int> seen[2] = {std::vector<int>(cols), std::vector<int>(cols)};
  std::vector<std::uint8_t> either(cols);  // masked in the block's rows
  for (int bv = 0; bv < half.rows; ++bv) {
    const int v[2] = {2 * bv, std::min(2 * bv + 1, mask.rows - 1)};
    const std::uint8_t* rows[2] = {mask.ptr<std::uint8_t>(v[0]), mask.ptr<std::uint8_t>(v[1])};
    either_row(rows[0], rows[1], mask.cols, either.data());
    const int first = next_set(either.data(), 0, mask.cols);
    if (first == mask.cols) continue;
    int last = mask.cols - 1;
    while (either[static_cast<std::size_t>(last)] == 0) --last;
    const int begin = first & ~1, end = std::min(mask.cols, (last | 1) + 1);  // whole blocks
    const float* depths[2];
    // Every pixel of the blocks' span projected at once (a loop that vectorises), then each block
    // takes its pixel's result.
    for (int r = 0; r < 2; ++r) {
      depths[r] = has_depth ? depth.ptr<float>(v[r]) : no_depth.data();
      const float by = (static_cast<float>(v[r]) - motion.cy) / motion.fy;
#ifdef LRD_AVX2_COPIES
      if (util::cpu_has_avx2()) {
        project_row_avx2(depths[r], bearing_x.data(), by, begin, end, motion, xs[r].data(), ys[r].data(),
                         seen[r].data());
        continue;
      }
#endif
      project_row_baseline(depths[r], bearing_x.data(), by, begin, end, motion, xs[r].data(), ys[r].data(),
                           seen[r].data());
    }
    for (int u = next_set(either.data(), begin, end); u < end; u = next_set(either.data(), u, end)) {
      const int u0 = u & ~1;
      u = u0 + 2;
      bool stays = false, moved = false;
      int su = 0, sr = 0;
      for (int k = 0; k < 4; ++k) {
        const int x = std::min(u0 + (k & 1), mask.cols - 1), r = k >> 1;
        if (rows[r][x] == 0) continue;
        if (!(depths[r][x] > 0.0f)) {
          stays = true;
        } else if (!moved) {
          moved = true, su = x, sr = r;
        }
      }
      if (stays) splat(half, u0 / 2, bv);
      if (!moved || seen[sr][static_cast<std::size_t>(su)] == 0)
        continue;  // behind the camera or out of view
      // The block's other pixels land within a pixel and a half of this one (the motion's
      // magnification), and propagate_mask splats each over 2x2 pixels: [x - 1.5, x + 2.5] holds them.
      const float x = xs[sr][static_cast<std::size_t>(su)], y = ys[sr][static_cast<std::size_t>(su)];
      fill_blocks(half, static_cast<int>(std::floor(0.5f * (x - 1.5f))),
                  static_cast<int>(std::floor(0.5f * (x + 2.5f))),
                  static_cast<int>(std::floor(0.5f * (y - 1.5f))),
                  static_cast<int>(std::floor(0.5f * (y + 2.5f))));
    }
  }
}

}  // namespace

cv::Mat propagate_mask(const cv::Mat& mask, const cv::Mat& depth, const Eigen::Isometry3d& T_t_k,
                       const camera::PinholeCamera& camera) {
  cv::Mat out = cv::Mat::zeros(mask.size(), CV_8UC1);
  // Without a usable depth image every pixel stays where it was.
  const bool has_depth = !depth.empty() && depth.type() == CV_32FC1 && depth.size() == mask.size();
  // Single precision and per-column bearings: this runs on every masked pixel of every frame whose
  // mask is older than the frame (async), a third of the image with people close by; sub-pixel
  // precision is irrelevant before the dilation that follows.
  const Eigen::Matrix3f R = T_t_k.linear().cast<float>();
  const Eigen::Vector3f t = T_t_k.translation().cast<float>();
  const auto fx = static_cast<float>(camera.fx), fy = static_cast<float>(camera.fy);
  const auto cx = static_cast<float>(camera.cx), cy = static_cast<float>(camera.cy);
  std::vector<float> bearing_x(static_cast<std::size_t>(mask.cols));
  for (int u = 0; u < mask.cols; ++u)
    bearing_x[static_cast<std::size_t>(u)] = (static_cast<float>(u) - cx) / fx;
  const auto round = [](float x) { return static_cast<int>(std::lrint(x)); };  // one instruction
  for (int v = 0; v < mask.rows; ++v) {
    const auto* m = mask.ptr<std::uint8_t>(v);
    const float* d = has_depth ? depth.ptr<float>(v) : nullptr;
    const float by = (static_cast<float>(v) - cy) / fy;
    // Row v's rays R * (bx, by, 1): the column term varies, the rest is shared.
    const Eigen::Vector3f row = R.col(1) * by + R.col(2);
    for (int u = 0; u < mask.cols; ++u) {
      if (m[u] == 0) continue;
      int ut = u, vt = v;
      if (d != nullptr && d[u] > 0.0f) {
        const Eigen::Vector3f q = (R.col(0) * bearing_x[static_cast<std::size_t>(u)] + row) * d[u] + t;
        if (q.z() <= 0.05f) continue;
        const float iz = 1.0f / q.z();
        ut = round(fx * q.x() * iz + cx);
        vt = round(fy * q.y() * iz + cy);
      }
      // A 2x2 splat closes the holes a forward warp leaves when the object comes closer.
      splat(out, ut, vt);
    }
  }
  return out;
}

cv::Mat dilated_mask(const cv::Mat& mask, int radius) {
  if (radius <= 0 || mask.empty()) return mask.clone();
  CV_Assert(mask.type() == CV_8UC1);
  cv::Mat out;
  dilate_into(mask, radius, out);
  return out;
}

void dilate_mask(cv::Mat& mask, int radius) {
  if (radius <= 0 || mask.empty()) return;
  dilated_mask(mask, radius).copyTo(mask);  // in place: headers sharing the caller's buffer see the result
}

cv::Mat carry_mask(const cv::Mat& mask, const cv::Mat& depth, const Eigen::Isometry3d& T_t_k,
                   const camera::PinholeCamera& camera, int radius) {
  if (radius < kHalfResolutionRadius) {
    cv::Mat out = propagate_mask(mask, depth, T_t_k, camera);
    dilate_mask(out, radius);
    return out;
  }
  // A mask about to grow by `radius` needs no single-pixel precision: 2x2 blocks move as one (a
  // quarter of the projections).
  BlockMotion motion{};
  const Eigen::Matrix3f R = T_t_k.linear().cast<float>();
  const Eigen::Vector3f t = T_t_k.translation().cast<float>();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) motion.r[3 * i + j] = R(i, j);
    motion.t[i] = t(i);
  }
  motion.fx = static_cast<float>(camera.fx), motion.fy = static_cast<float>(camera.fy);
  motion.cx = static_cast<float>(camera.cx), motion.cy = static_cast<float>(camera.cy);
  motion.width = static_cast<float>(mask.cols), motion.height = static_cast<float>(mask.rows);
  cv::Mat half = cv::Mat::zeros((mask.rows + 1) / 2, (mask.cols + 1) / 2, CV_8UC1);
  carry_blocks(mask, depth, motion, half);
  // Every block the exact propagation sets is set; two pixels r apart lie at most r / 2 + 0.71
  // blocks apart, so a half-resolution disc of (radius + 1) / 2 + 1 blocks covers the full one.
  cv::Mat grown, out;
  dilate_into(half, (radius + 1) / 2 + 1, grown);
  upsample_blocks(grown, mask.size(), out);
  return out;
}

}  // namespace lrd::dynamic
