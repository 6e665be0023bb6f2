#include "lrd/dense/cloud_renderer.h"

#include <cmath>
#include <limits>

namespace lrd::dense {

cv::Mat render_cloud(const PointCloud& cloud, const camera::PinholeCamera& camera,
                     const Eigen::Isometry3d& T_wc, int point_px) {
  cv::Mat image(camera.height, camera.width, CV_8UC3, cv::Scalar(40, 40, 40));
  cv::Mat zbuf(camera.height, camera.width, CV_32F, cv::Scalar(std::numeric_limits<float>::infinity()));
  const Eigen::Isometry3f T_cw = T_wc.inverse().cast<float>();
  const bool coloured = cloud.colours.size() == cloud.points.size();
  const int half = point_px / 2;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3f p = T_cw * cloud.points[i];
    if (p.z() < 0.1f) continue;
    const float fu =
        std::floor(static_cast<float>(camera.fx) * p.x() / p.z() + static_cast<float>(camera.cx) + 0.5f);
    const float fv =
        std::floor(static_cast<float>(camera.fy) * p.y() / p.z() + static_cast<float>(camera.cy) + 0.5f);
    if (!(fu > -4.0f && fv > -4.0f && fu < static_cast<float>(camera.width + 4) &&
          fv < static_cast<float>(camera.height + 4)))
      continue;  // outside the picture (or not a number): no cast of a huge float
    const int u = static_cast<int>(fu), v = static_cast<int>(fv);
    for (int dv = -half; dv < point_px - half; ++dv)
      for (int du = -half; du < point_px - half; ++du) {
        const int x = u + du, y = v + dv;
        if (x < 0 || y < 0 || x >= camera.width || y >= camera.height) continue;
        float& z = zbuf.at<float>(y, x);
        if (p.z() >= z) continue;
        z = p.z();
        image.at<cv::Vec3b>(y, x) = coloured ? cloud.colours[i] : cv::Vec3b(200, 200, 200);
      }
  }
  return image;
}

Eigen::Isometry3d overview_pose(const PointCloud& cloud, const Eigen::Isometry3d& reference, double back,
                                double up) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3f& p : cloud.points) centroid += p.cast<double>();
  if (!cloud.points.empty()) centroid /= static_cast<double>(cloud.size());
  const Eigen::Matrix3d R = reference.linear();
  // Camera axes: x right, y down, z forward.
  const Eigen::Vector3d eye = reference.translation() - back * R.col(2) - up * R.col(1);
  Eigen::Vector3d z = centroid - eye;
  if (z.norm() < 1e-6) z = R.col(2);
  z.normalize();
  Eigen::Vector3d x = z.cross(-R.col(1));                   // right = forward x up
  if (x.norm() < 1e-6) x = R.col(0) - R.col(0).dot(z) * z;  // looking straight up or down
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();
  T_wc.linear().col(0) = x;
  T_wc.linear().col(1) = y;
  T_wc.linear().col(2) = z;
  T_wc.translation() = eye;
  return T_wc;
}

}  // namespace lrd::dense
