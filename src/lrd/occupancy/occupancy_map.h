#pragma once
// The 3-D occupancy map (issue 25): an OctoMap OcTree filled by ray casting each keyframe's
// depth. Along each ray the voxels are free, at its end occupied; the end's evidence shrinks with
// the sensor's depth noise, sigma(z) = depth_noise * z^2: the hit adds the log-odds of
//   p(z) = 0.5 + (prob_hit - 0.5) * erf(resolution / (2 sqrt(2) sigma(z))),
// the chance that a surface measured at z lies in the voxel it was measured in. Free-space
// carving is what removes a person who stood somewhere and walked on: later rays pass through.
// OctoMap stays behind this interface (its headers are not part of lrd-slam's).
#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

#include "lrd/occupancy/occupancy_params.h"

namespace lrd::occupancy {

enum class VoxelState { Unknown, Free, Occupied };

// One keyframe's depth as rays: the camera centre and the measured points, in the map frame.
// Points with hit[i] == false only carve free space (seen through by other keyframes, so not a
// surface to keep); depth[i] is the measurement's z in its camera, for the noise model.
struct RayBundle {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3f> points;
  std::vector<float> depth;
  std::vector<char> hit;
};

class OccupancyMap {
 public:
  explicit OccupancyMap(const OccupancyParams& params);
  ~OccupancyMap();
  OccupancyMap(OccupancyMap&&) noexcept;
  OccupancyMap& operator=(OccupancyMap&&) noexcept;

  // Casts every ray: each voxel updated at most once per bundle, a hit wins over free space.
  void integrate(const RayBundle& rays);

  [[nodiscard]] double resolution() const;
  [[nodiscard]] VoxelState state_at(const Eigen::Vector3d& p) const;
  // Whether one of the 26 voxels around the voxel at p is occupied.
  [[nodiscard]] bool has_occupied_neighbour(const Eigen::Vector3d& p) const;
  // Centres of the occupied leaf voxels at full resolution (pruned nodes expanded).
  [[nodiscard]] std::vector<Eigen::Vector3d> occupied_voxels() const;
  // Known voxels at full resolution in `state` (Occupied or Free).
  [[nodiscard]] std::size_t count(VoxelState state) const;
  [[nodiscard]] std::size_t occupied_count() const { return count(VoxelState::Occupied); }
  [[nodiscard]] std::size_t free_count() const { return count(VoxelState::Free); }
  // Calls fn(centre, occupied) for every known voxel at full resolution (pruned nodes expanded).
  void visit(const std::function<void(const Eigen::Vector3d&, bool)>& fn) const;

  // OctoMap's binary format (.bt: occupied / free bits; octovis opens it).
  void write_binary(const std::filesystem::path& file) const;
  [[nodiscard]] static OccupancyMap read_binary(const std::filesystem::path& file,
                                                const OccupancyParams& params);

  // The log-odds a hit at depth z adds (see above); exposed for tests.
  [[nodiscard]] static float hit_log_odds(const OccupancyParams& params, double z);

 private:
  struct Tree;
  OccupancyParams params_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace lrd::occupancy
