#include "lrd/dense/background_repairer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

namespace lrd::dense {

BackgroundRepairer::BackgroundRepairer(const camera::PinholeCamera& camera, const RepairParams& params)
    : camera_(camera), params_(params) {}

cv::Rect BackgroundRepairer::source_window(const cv::Rect& box, const Eigen::Isometry3d& T_st,
                                           const cv::Size& size) const {
  // The target pixels of `box` at any depth the repair uses fill a convex frustum; its image in
  // the source is the convex hull of its 8 corners' projections, so only the source pixels in
  // their bounding box can land in the box. A corner behind the source camera: the whole image.
  const double near = 0.3, far = params_.max_depth;  // depth sensors measure nothing nearer
  double u0 = 1e9, v0 = 1e9, u1 = -1e9, v1 = -1e9;
  for (const int x : {box.x, box.x + box.width})
    for (const int y : {box.y, box.y + box.height})
      for (const double z : {near, far}) {
        const Eigen::Vector3d p = T_st * camera_.unproject(x, y, z);
        if (p.z() <= 0.05) return {0, 0, size.width, size.height};
        const double u = camera_.fx * p.x() / p.z() + camera_.cx, v = camera_.fy * p.y() / p.z() + camera_.cy;
        u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
      }
  const int margin = 2;  // the 2x2 splat
  const cv::Rect window(cv::Point(static_cast<int>(std::floor(std::max(u0, -1.0))) - margin,
                                  static_cast<int>(std::floor(std::max(v0, -1.0))) - margin),
                        cv::Point(static_cast<int>(std::ceil(std::min(u1, size.width + 1.0))) + margin,
                                  static_cast<int>(std::ceil(std::min(v1, size.height + 1.0))) + margin));
  return window & cv::Rect(0, 0, size.width, size.height);
}

RepairResult BackgroundRepairer::repair(const RgbdView& target,
                                        const std::vector<const RgbdView*>& sources) const {
  RepairResult r;
  r.bgr = target.bgr.clone();
  r.depth = target.depth.clone();
  r.filled = cv::Mat::zeros(target.depth.size(), CV_8UC1);
  if (target.dynamic.empty()) return r;
  const cv::Mat& region = target.dynamic;
  r.dynamic_pixels = cv::countNonZero(region);
  if (r.dynamic_pixels == 0) return r;
  const cv::Rect box = cv::boundingRect(region);
  // The dynamic region starts empty; sources write into it nearest-first.
  r.bgr.setTo(cv::Scalar::all(0), region);
  r.depth.setTo(0.0f, region);
  // Per pixel, the front surface seen so far: its nearest depth, and the sums of the samples
  // within a band behind it. Averaging them (rather than keeping the nearest sample) removes the
  // sensor noise's pull towards the camera that a plain minimum over many sources has.
  cv::Mat zbuf(target.depth.size(), CV_32F, cv::Scalar(std::numeric_limits<float>::infinity()));
  cv::Mat zsum(target.depth.size(), CV_32F, cv::Scalar(0)),
      csum(target.depth.size(), CV_32FC3, cv::Scalar::all(0));
  cv::Mat count(target.depth.size(), CV_32F, cv::Scalar(0));
  const auto band = static_cast<float>(params_.surface_band);
  const double fx = camera_.fx, fy = camera_.fy, cx = camera_.cx, cy = camera_.cy;
  const int w = target.depth.cols, h = target.depth.rows;
  // Every stride-th source pixel, each covering the (stride + 1)^2 target pixels around where it
  // lands, so a slight change of viewpoint leaves no cracks.
  const int stride = params_.pixel_stride, splat = stride + 1;
  for (const RgbdView* src : sources) {
    if (src == nullptr || src->depth.empty()) continue;
    const Eigen::Isometry3d T_ts = target.T_cw * src->T_cw.inverse();
    const Eigen::Matrix3d R = T_ts.linear();
    const Eigen::Vector3d t = T_ts.translation();
    const bool src_masked = !src->dynamic.empty();
    const cv::Rect rows_cols = source_window(box, T_ts.inverse(), src->depth.size());
    for (int v = rows_cols.y; v < rows_cols.y + rows_cols.height; v += stride) {
      const float* zrow = src->depth.ptr<float>(v);
      const unsigned char* mrow = src_masked ? src->dynamic.ptr<unsigned char>(v) : nullptr;
      const cv::Vec3b* crow = src->bgr.ptr<cv::Vec3b>(v);
      // The row's rays, so each pixel costs one scaled add and a projection.
      const Eigen::Vector3d row_base = R * Eigen::Vector3d(-cx / fx, (v - cy) / fy, 1.0);
      const Eigen::Vector3d du = R.col(0) / fx;
      for (int u = rows_cols.x; u < rows_cols.x + rows_cols.width; u += stride) {
        const float z = zrow[u];
        if (!(z > 0.0f && z <= params_.max_depth) || (mrow != nullptr && mrow[u] != 0)) continue;  // NaN too
        const Eigen::Vector3d p = (row_base + du * u) * z + t;
        if (p.z() < 0.05) continue;
        const double pu = fx * p.x() / p.z() + cx, pv = fy * p.y() / p.z() + cy;
        const double half = 0.5 * splat - 0.5;
        const int u0 = static_cast<int>(std::floor(pu - half)), v0 = static_cast<int>(std::floor(pv - half));
        if (u0 + splat <= box.x || v0 + splat <= box.y || u0 >= box.x + box.width || v0 >= box.y + box.height)
          continue;
        if (on_depth_edge(src->depth, u, v, params_.depth_edge)) continue;
        const float zt = static_cast<float>(p.z());
        for (int dv = 0; dv < splat; ++dv) {
          const int tv = v0 + dv;
          if (tv < 0 || tv >= h) continue;
          for (int dx = 0; dx < splat; ++dx) {
            const int tu = u0 + dx;
            if (tu < 0 || tu >= w || region.at<unsigned char>(tv, tu) == 0) continue;
            float& best = zbuf.at<float>(tv, tu);
            if (zt > best * (1.0f + band)) continue;  // behind the front surface
            float& n = count.at<float>(tv, tu);
            float& sum = zsum.at<float>(tv, tu);
            cv::Vec3f& c = csum.at<cv::Vec3f>(tv, tu);
            if (zt < best * (1.0f - band)) n = 0.0f, sum = 0.0f, c = cv::Vec3f();  // a new front surface
            best = std::min(best, zt);
            n += 1.0f;
            sum += zt;
            c += cv::Vec3f(crow[u][0], crow[u][1], crow[u][2]);
          }
        }
      }
    }
  }
  r.filled = (count > 0.0f) & (region != 0);
  for (int v = box.y; v < box.y + box.height; ++v)
    for (int u = box.x; u < box.x + box.width; ++u) {
      const float n = count.at<float>(v, u);
      if (n <= 0.0f || region.at<unsigned char>(v, u) == 0) continue;
      r.depth.at<float>(v, u) = zsum.at<float>(v, u) / n;
      const cv::Vec3f c = csum.at<cv::Vec3f>(v, u) / n;
      r.bgr.at<cv::Vec3b>(v, u) = cv::Vec3b(cv::saturate_cast<uchar>(c[0]), cv::saturate_cast<uchar>(c[1]),
                                            cv::saturate_cast<uchar>(c[2]));
    }
  r.filled_pixels = cv::countNonZero(r.filled);
  return r;
}

}  // namespace lrd::dense
