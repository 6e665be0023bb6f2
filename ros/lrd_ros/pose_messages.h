#pragma once
// Rigid transforms to and from geometry_msgs, in one place (the bag writer's /tf, the bag
// reader's ground truth, the node's pose, tf and world frame).
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>

#include <Eigen/Geometry>

namespace lrd_ros {

[[nodiscard]] geometry_msgs::Pose pose_message(const Eigen::Isometry3d& T);
[[nodiscard]] geometry_msgs::Transform transform_message(const Eigen::Isometry3d& T);
// The quaternion is normalised (messages carry rounded ones).
[[nodiscard]] Eigen::Isometry3d from_message(const geometry_msgs::Transform& t);

}  // namespace lrd_ros
