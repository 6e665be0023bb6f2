#pragma once
// Stamped camera trajectories and their text formats (TUM RGB-D and KITTI odometry).
// Poses are camera-to-world, as in the TUM ground-truth files.
#include <Eigen/Geometry>
#include <filesystem>
#include <optional>
#include <vector>

namespace lrd::io {

struct StampedPose {
  double timestamp = 0.0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // camera-to-world
};

using Trajectory = std::vector<StampedPose>;

// Reads "timestamp tx ty tz qx qy qz qw" lines the way TUM's evaluate_rpe.py does: commas and tabs
// separate fields, lines starting with '#' and blank lines are skipped, entries with a NaN or an
// all-zero quaternion are skipped, the quaternion is normalized. Returns poses sorted by timestamp.
// Throws lrd::Error naming FILE:LINE for a wrong field count, a non-numeric or infinite field, or
// a duplicate timestamp, and naming FILE when it cannot be read.
[[nodiscard]] Trajectory read_trajectory_tum(const std::filesystem::path& file);

// "t tx ty tz qx qy qz qw", timestamp with 6 decimals, values with 9, after a '#' header line.
void write_trajectory_tum(const std::filesystem::path& file, const Trajectory& trajectory);

// The pose at time t of a trajectory sorted by timestamp: a sample stamped t itself, else the
// two samples around t at most max_gap apart, interpolated (position linearly, rotation by slerp).
// A motion-capture ground truth (TUM: 100 Hz, its own clock) has no sample at an image's stamp.
// nullopt outside the trajectory or across a longer gap.
[[nodiscard]] std::optional<Eigen::Isometry3d> pose_at(const Trajectory& trajectory, double t,
                                                       double max_gap);

// KITTI odometry poses: the 12 values of the row-major 3x4 [R|t] per line (no timestamps).
void write_trajectory_kitti(const std::filesystem::path& file, const Trajectory& trajectory);

}  // namespace lrd::io
