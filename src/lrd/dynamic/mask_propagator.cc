#include "lrd/dynamic/mask_propagator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <vector>

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
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) half.at<std::uint8_t>(y, x) = 255;
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

void dilate_mask(cv::Mat& mask, int radius) {
  if (radius <= 0 || mask.empty()) return;
  CV_Assert(mask.type() == CV_8UC1);
  // Each run of set pixels is written, widened by the disc's half-width, into the 2r+1 rows the
  // disc covers: the cost follows the masked area, not the disc's, where cv::dilate with an
  // elliptic element grew with the radius (640x480: radius 7 0.46 ms, 11 1.0 ms, 31 ~15 ms).
  const std::vector<int> w = disc_half_widths(radius);
  cv::Mat out = cv::Mat::zeros(mask.size(), CV_8UC1);
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
  out.copyTo(mask);  // in place: headers sharing the caller's buffer see the result
}

cv::Mat carry_mask(const cv::Mat& mask, const cv::Mat& depth, const Eigen::Isometry3d& T_t_k,
                   const camera::PinholeCamera& camera, int radius) {
  if (radius < kHalfResolutionRadius) {
    cv::Mat out = propagate_mask(mask, depth, T_t_k, camera);
    dilate_mask(out, radius);
    return out;
  }
  // A mask about to grow by `radius` needs no single-pixel precision: each 2x2 block moves as one
  // (a quarter of the projections), with its first masked pixel that has depth; a block with
  // masked pixels without depth also stays where it was, as those pixels do in propagate_mask.
  const bool has_depth = !depth.empty() && depth.type() == CV_32FC1 && depth.size() == mask.size();
  const Eigen::Matrix3f R = T_t_k.linear().cast<float>();
  const Eigen::Vector3f t = T_t_k.translation().cast<float>();
  const auto fx = static_cast<float>(camera.fx), fy = static_cast<float>(camera.fy);
  const auto cx = static_cast<float>(camera.cx), cy = static_cast<float>(camera.cy);
  cv::Mat half = cv::Mat::zeros((mask.rows + 1) / 2, (mask.cols + 1) / 2, CV_8UC1);
  std::vector<std::uint8_t> either(static_cast<std::size_t>(mask.cols));  // masked in the block's rows
  for (int bv = 0; bv < half.rows; ++bv) {
    const int v0 = 2 * bv, v1 = std::min(v0 + 1, mask.rows - 1);
    const std::uint8_t* rows[2] = {mask.ptr<std::uint8_t>(v0), mask.ptr<std::uint8_t>(v1)};
    const float* depths[2] = {has_depth ? depth.ptr<float>(v0) : nullptr,
                              has_depth ? depth.ptr<float>(v1) : nullptr};
    for (int u = 0; u < mask.cols; ++u) either[static_cast<std::size_t>(u)] = rows[0][u] | rows[1][u];
    for (int u = next_set(either.data(), 0, mask.cols); u < mask.cols;
         u = next_set(either.data(), u, mask.cols)) {
      const int u0 = u & ~1;
      u = u0 + 2;
      bool stays = false, moved = false;
      int su = 0, sv = 0;
      float sd = 0.0f;
      for (int k = 0; k < 4; ++k) {
        const int x = std::min(u0 + (k & 1), mask.cols - 1), r = k >> 1;
        if (rows[r][x] == 0) continue;
        const float d = depths[r] != nullptr ? depths[r][x] : 0.0f;
        if (!(d > 0.0f)) {
          stays = true;
        } else if (!moved) {
          moved = true, su = x, sv = r == 0 ? v0 : v1, sd = d;
        }
      }
      if (stays) splat(half, u0 / 2, bv);
      if (!moved) continue;
      const Eigen::Vector3f ray((static_cast<float>(su) - cx) / fx, (static_cast<float>(sv) - cy) / fy, 1.0f);
      const Eigen::Vector3f q = R * ray * sd + t;
      if (q.z() <= 0.05f) continue;
      const float x = fx * q.x() / q.z() + cx, y = fy * q.y() / q.z() + cy;
      if (!(x > -2.0f && y > -2.0f && x < static_cast<float>(mask.cols) + 2.0f &&
            y < static_cast<float>(mask.rows) + 2.0f))
        continue;  // out of view (or not a number)
      // The block's other pixels land within a pixel and a half of this one (the motion's
      // magnification), and propagate_mask splats each over 2x2 pixels: [x - 1.5, x + 2.5] holds them.
      fill_blocks(half, static_cast<int>(std::floor(0.5f * (x - 1.5f))),
                  static_cast<int>(std::floor(0.5f * (x + 2.5f))),
                  static_cast<int>(std::floor(0.5f * (y - 1.5f))),
                  static_cast<int>(std::floor(0.5f * (y + 2.5f))));
    }
  }
  // Every block the exact propagation sets is set; two pixels r apart lie at most r / 2 + 0.71
  // blocks apart, so a half-resolution disc of (radius + 1) / 2 + 1 blocks covers the full one.
  dilate_mask(half, (radius + 1) / 2 + 1);
  cv::Mat out;
  cv::resize(half, out, mask.size(), 0.0, 0.0, cv::INTER_NEAREST);
  return out;
}

}  // namespace lrd::dynamic
