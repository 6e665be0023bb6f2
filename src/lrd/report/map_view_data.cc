#include "lrd/report/map_view_data.h"

#include <bit>
#include <cstring>
#include <string>

#include "lrd/dense/ply_io.h"
#include "lrd/io/trajectory.h"
#include "lrd/report/html_page.h"
#include "lrd/report/trajectory_data.h"

namespace lrd::report {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

static_assert(std::endian::native == std::endian::little, "the page reads float32 little-endian");

// Every stride-th point of the cloud (all when it is small enough), with its colour when it has one.
json cloud_json(const dense::PointCloud& cloud, std::size_t max_points) {
  const std::size_t stride = stride_for(cloud.size(), max_points);
  const bool coloured = cloud.colours.size() == cloud.size();
  std::string positions, colours;
  std::size_t count = 0;
  for (std::size_t i = 0; i < cloud.size(); i += stride, ++count) {
    const Eigen::Vector3f& p = cloud.points[i];
    char bytes[3 * sizeof(float)];
    std::memcpy(bytes, p.data(), sizeof(bytes));
    positions.append(bytes, sizeof(bytes));
    if (coloured) {
      const cv::Vec3b& bgr = cloud.colours[i];
      colours += {static_cast<char>(bgr[2]), static_cast<char>(bgr[1]), static_cast<char>(bgr[0])};
    }
  }
  json j = {{"count", count}, {"of", cloud.size()}, {"positions", base64(positions)}};
  if (coloured) j["colours"] = base64(colours);
  return j;
}

}  // namespace

std::optional<json> map_view_data(const fs::path& run_dir) {
  const fs::path dense_file = run_dir / "dense_map.ply",
                 sparse_file = run_dir / "report_frames" / "sparse_map.ply";
  if (!fs::exists(dense_file) && !fs::exists(sparse_file)) return std::nullopt;
  json j = json::object();
  if (fs::exists(dense_file)) j["dense"] = cloud_json(dense::read_ply(dense_file), kMaxDensePoints);
  if (fs::exists(sparse_file)) j["sparse"] = cloud_json(dense::read_ply(sparse_file), kMaxDensePoints);
  const fs::path keyframes_file = run_dir / "KeyFrameTrajectory.txt";
  json keyframes = xyz_columns();
  if (fs::exists(keyframes_file))
    for (const io::StampedPose& k : io::read_trajectory_tum(keyframes_file))
      push_xyz(keyframes, k.pose.translation());
  j["keyframes"] = keyframes;
  return j;
}

}  // namespace lrd::report
