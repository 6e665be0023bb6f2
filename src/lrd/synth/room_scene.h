#pragma once
// The static room of the synthetic benchmark: 6 x 5 x 3 m, world frame with z up, floor at z = 0,
// x along the room's length. The camera of most presets stands near x = 2.2 looking towards +x,
// at a desk with a monitor before a wall of posters, like the TUM fr3 office scenes.
#include <Eigen/Geometry>
#include <vector>

#include "lrd/synth/texture_library.h"
#include "lrd/synth/triangle_soup.h"

namespace lrd::synth {

struct RoomLayout {
  static constexpr float kLength = 6.0f;  // x
  static constexpr float kWidth = 5.0f;   // y
  static constexpr float kHeight = 3.0f;  // z
  // Desk before the front wall, long side along y, and the chairs behind it facing the camera.
  static Eigen::Vector3f desk_center() { return {4.6f, 2.5f, 0.0f}; }
  static constexpr float kDeskLength = 2.0f;
  static constexpr float kDeskDepth = 0.8f;
  // Chair poses (origin on the floor, +x = the direction a seated person faces).
  static std::vector<Eigen::Isometry3f> seat_poses();
};

// Builds every static surface of the room (walls, floor, ceiling, posters, furniture).
[[nodiscard]] TriangleSoup build_room(const TextureLibrary& tex);

// Pose with origin `p` on the floor and +x rotated by `yaw` (radians) about z.
[[nodiscard]] Eigen::Isometry3f floor_pose(float x, float y, float yaw, float z = 0.0f);

}  // namespace lrd::synth
