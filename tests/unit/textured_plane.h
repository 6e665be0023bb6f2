#pragma once
// A textured plane seen by an ideal RGB-D camera (TUM fr3 intrinsics, no distortion), rendered
// exactly from any pose: a grey image and a metric depth image. Far cheaper than the synthetic
// room (a frame renders and extracts in about 25 ms in a release build) and with exact ground truth: the
// world point behind any pixel is a ray-plane intersection. The world frame is the camera frame
// of the identity pose; the plane is tilted so that depth varies over the image.
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <map>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/data/frame.h"
#include "lrd/features/keypoint_undistorter.h"
#include "lrd/features/orb_extractor.h"
#include "lrd/map/map.h"

namespace lrd::test {

class TexturedPlane {
 public:
  static constexpr int kTextureSize = 1024;  // power of two: wrapping is a mask

  explicit TexturedPlane(std::uint64_t seed = 7, double distance = 2.2,
                         const Eigen::Vector3d& normal = Eigen::Vector3d(0.25, -0.15, -1.0))
      : camera_(camera::camera_preset("tum3")),
        extractor_(features::OrbParams{}),
        undistorter_(camera_),
        texture_(shared_texture(seed)),
        origin_(0.0, 0.0, distance),
        normal_(normal.normalized()) {
    e1_ = (Eigen::Vector3d::UnitX() - normal_.x() * normal_).normalized();
    e2_ = normal_.cross(e1_);
  }

  [[nodiscard]] const camera::PinholeCamera& camera() const { return camera_; }
  // The depth noise model of the frames rendered from now on.
  void set_disparity_sigma(double sigma) { camera_.disparity_sigma = sigma; }

  // World point seen at the (undistorted) pixel (u, v) by the camera at T_cw; empty when the
  // plane is not in front of it.
  [[nodiscard]] std::optional<Eigen::Vector3d> intersect(const Eigen::Isometry3d& T_cw, double u,
                                                         double v) const {
    const Eigen::Isometry3d T_wc = T_cw.inverse();
    const Eigen::Vector3d ray =
        T_wc.linear() * Eigen::Vector3d((u - camera_.cx) / camera_.fx, (v - camera_.cy) / camera_.fy, 1.0);
    const double den = normal_.dot(ray);
    if (std::abs(den) < 1e-12) return std::nullopt;
    const double lambda = normal_.dot(origin_ - T_wc.translation()) / den;  // = depth (ray has z = 1)
    if (lambda <= 0.0) return std::nullopt;
    return Eigen::Vector3d(T_wc.translation() + lambda * ray);
  }

  struct Image {
    cv::Mat grey;   // CV_8U
    cv::Mat depth;  // CV_32F metres
  };

  // Bilinear texture lookup per pixel; depth of the plane per pixel.
  [[nodiscard]] Image render(const Eigen::Isometry3d& T_cw) const {
    Image img{cv::Mat(camera_.height, camera_.width, CV_8U), cv::Mat(camera_.height, camera_.width, CV_32F)};
    const Eigen::Isometry3d T_wc = T_cw.inverse();
    constexpr int mask = kTextureSize - 1;
    const Eigen::Matrix3d R_wc = T_wc.linear();
    const Eigen::Vector3d C = T_wc.translation();
    const double plane_d = normal_.dot(origin_ - C);
    for (int v = 0; v < camera_.height; ++v) {
      auto* g = img.grey.ptr<std::uint8_t>(v);
      auto* d = img.depth.ptr<float>(v);
      for (int u = 0; u < camera_.width; ++u) {
        const Eigen::Vector3d ray =
            R_wc * Eigen::Vector3d((u - camera_.cx) / camera_.fx, (v - camera_.cy) / camera_.fy, 1.0);
        const double den = normal_.dot(ray);
        const double lambda = std::abs(den) < 1e-12 ? -1.0 : plane_d / den;
        if (lambda <= 0.0) {
          g[u] = 0;
          d[u] = 0.0f;
          continue;
        }
        d[u] = static_cast<float>(lambda);
        const Eigen::Vector3d rel = C + lambda * ray - origin_;
        const double tx = rel.dot(e1_) * kTexelsPerMetre - 0.5, ty = rel.dot(e2_) * kTexelsPerMetre - 0.5;
        const double fx = std::floor(tx), fy = std::floor(ty);
        const double ax = tx - fx, ay = ty - fy;
        const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
        const int x0 = ix & mask, x1 = (ix + 1) & mask, y0 = iy & mask, y1 = (iy + 1) & mask;
        const auto* r0 = texture_.ptr<std::uint8_t>(y0);
        const auto* r1 = texture_.ptr<std::uint8_t>(y1);
        const double val =
            (1 - ax) * (1 - ay) * r0[x0] + ax * (1 - ay) * r0[x1] + (1 - ax) * ay * r1[x0] + ax * ay * r1[x1];
        g[u] = cv::saturate_cast<std::uint8_t>(val);
      }
    }
    return img;
  }

  // Features of the view from T_cw, with the pose set. Depth is dropped (0) where `no_depth` is
  // nonzero, to get keypoints without a virtual right coordinate (monocular observations).
  // `dynamic`: the frame's dynamic mask (CV_8UC1, nonzero: a person; no features there).
  data::Frame frame(std::uint64_t id, const Eigen::Isometry3d& T_cw, const cv::Mat& no_depth = cv::Mat(),
                    const cv::Mat& dynamic = cv::Mat()) {
    Image img = render(T_cw);
    if (!no_depth.empty()) img.depth.setTo(0.0f, no_depth);
    data::Frame f(id, 0.1 * static_cast<double>(id), img.grey, img.depth, dynamic, extractor_, undistorter_,
                  camera_);
    f.set_pose(T_cw);
    return f;
  }

  // Reprojection error (pixels) of keypoint i of `f` against the true projection of world point x
  // into f's camera at T_cw.
  [[nodiscard]] double pixel_error(const data::Frame& f, std::size_t i, const Eigen::Isometry3d& T_cw,
                                   const Eigen::Vector3d& x) const {
    const Eigen::Vector3d pc = T_cw * x;
    if (pc.z() <= 0.0) return 1e9;
    const Eigen::Vector2d uv = camera_.project(pc);
    const cv::Point2f& p = f.undistorted()[i].pt;
    return (uv - Eigen::Vector2d(p.x, p.y)).norm();
  }

  // The exact world point behind keypoint i of `f` (seen from T_cw).
  [[nodiscard]] Eigen::Vector3d true_point(const data::Frame& f, std::size_t i,
                                           const Eigen::Isometry3d& T_cw) const {
    const cv::Point2f& p = f.undistorted()[i].pt;
    return *intersect(T_cw, p.x, p.y);
  }

 private:
  static constexpr double kTexelsPerMetre = 270.0;  // about one texel per pixel at 2 m

  // Textures are made once per seed and shared (read-only) by every scene of the process.
  static cv::Mat shared_texture(std::uint64_t seed) {
    static std::mutex mutex;
    static std::map<std::uint64_t, cv::Mat> cache;
    const std::lock_guard lock(mutex);
    auto it = cache.find(seed);
    if (it == cache.end()) it = cache.emplace(seed, make_texture(seed)).first;
    return it->second;
  }

  // Random filled polygons, rectangles and discs of random grey over a noisy background, lightly
  // blurred: corners at every scale and in every orientation.
  static cv::Mat make_texture(std::uint64_t seed) {
    cv::RNG rng(seed);
    cv::Mat t(kTextureSize, kTextureSize, CV_8U);
    rng.fill(t, cv::RNG::UNIFORM, 90, 166);
    cv::GaussianBlur(t, t, cv::Size(0, 0), 3.0);
    for (int k = 0; k < 2600; ++k) {
      const int size = k < 300 ? rng.uniform(25, 70) : rng.uniform(4, 25);
      const cv::Point c(rng.uniform(0, kTextureSize), rng.uniform(0, kTextureSize));
      const cv::Scalar grey(rng.uniform(0, 256));
      switch (rng.uniform(0, 3)) {
        case 0: {
          std::vector<cv::Point> poly;
          const int n = rng.uniform(3, 6);
          for (int j = 0; j < n; ++j)
            poly.emplace_back(c.x + rng.uniform(-size, size + 1), c.y + rng.uniform(-size, size + 1));
          cv::fillConvexPoly(t, poly, grey, cv::LINE_AA);
          break;
        }
        case 1:
          cv::rectangle(t, cv::Rect(c.x, c.y, rng.uniform(3, size + 4), rng.uniform(3, size + 4)), grey,
                        cv::FILLED);
          break;
        default:
          cv::circle(t, c, std::max(2, size / 2), grey, cv::FILLED, cv::LINE_AA);
      }
    }
    cv::GaussianBlur(t, t, cv::Size(0, 0), 0.8);
    return t;
  }

  camera::PinholeCamera camera_;
  features::OrbExtractor extractor_;
  features::KeypointUndistorter undistorter_;
  cv::Mat texture_;
  Eigen::Vector3d origin_, normal_, e1_, e2_;
};

// A keyframe of `frame` with a map point for every keypoint that has depth (as tracking's map
// initialization does), or with `unmatched_only` for those without a match yet (as a new keyframe
// of tracking). Returns the keyframe.
inline map::KeyFrame* keyframe_with_points(map::Map& map, const data::Frame& frame,
                                           bool unmatched_only = false) {
  map::KeyFrame* kf = map.create_keyframe(frame);
  for (std::size_t i = 0; i < frame.size(); ++i) {
    if (unmatched_only && frame.map_points[i] != nullptr) continue;
    const auto x = frame.unproject_world(i);
    if (!x) continue;
    map::MapPoint* mp = map.create_map_point(*x, kf, frame.id());
    mp->add_observation(kf, i);
    kf->add_map_point(mp, i);
    mp->compute_distinctive_descriptor();
    mp->update_normal_and_depth();
  }
  return kf;
}

// A pose from a twist (omega, nu) in the convention of geometry::se3_exp.
inline Eigen::Isometry3d pose(double wx, double wy, double wz, double tx, double ty, double tz) {
  geometry::Vector6d xi;
  xi << wx, wy, wz, tx, ty, tz;
  return geometry::se3_exp(xi);
}

inline double rotation_error_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
}

}  // namespace lrd::test
