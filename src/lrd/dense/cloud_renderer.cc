#include "lrd/dense/cloud_renderer.h"

#include <limits>

namespace lrd::dense {

cv::Mat render_cloud(const PointCloud& cloud, const camera::PinholeCamera& camera, const Eigen::Isometry3d& T_wc,
                     int point_px) {
  cv::Mat image(camera.height, camera.width, CV_8UC3, cv::Scalar(40, 40, 40));
  cv::Mat zbuf(camera.height, camera.width, CV_32F, cv::Scalar(std::numeric_limits<float>::infinity()));
  const Eigen::Isometry3f T_cw = T_wc.inverse().cast<float>();
  const bool coloured = cloud.colours.size() == cloud.points.size();
  const int half = point_px / 2;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3f p = T_cw * cloud.points[i];
    if (p.z() < 0.1f) continue;
    const int u = static_cast<int>(camera.fx * p.x() / p.z() + camera.cx);
    const int v = static_cast<int>(camera.fy * p.y() / p.z() + camera.cy);
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

Eigen::Isometry3d overview_pose(const PointCloud& cloud, const Eigen::Isometry3d& reference, double back, double up) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3f& p : cloud.points) centroid += p.cast<double>();
  if (!cloud.points.empty()) centroid /= static_cast<double>(cloud.size());
  const Eigen::Matrix3d R = reference.linear();
  // Camera axes: x right, y down, z forward.
  const Eigen::Vector3d eye = reference.translation() - back * R.col(2) - up * R.col(1);
  Eigen::Vector3d z = centroid - eye;
  if (z.norm() < 1e-6) z = R.col(2);
  z.normalize();
  Eigen::Vector3d x = z.cross(-R.col(1));  // right = forward x up
  if (x.norm() < 1e-6) x = R.col(0);
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
