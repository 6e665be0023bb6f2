#pragma once
// The 3-D occupancy map (docs/occupancy.md): an OctoMap OcTree filled by ray casting each
// keyframe's depth. Along each ray the voxels are free, at its end occupied; the end's evidence
// shrinks with the sensor's depth noise, sigma(z) = depth_noise * z^2: the hit adds the log-odds of
//   p(z) = 0.5 + (prob_hit - 0.5) * erf(resolution / (2 sqrt(2) sigma(z))),
// the chance that a surface measured at z lies in the voxel it was measured in. Free-space
// carving is what removes a person who stood somewhere and walked on: later rays pass through.
// A voxel hit next to a dynamic region becomes a surface once min_hit_keyframes keyframes have
// measured it, at least min_hit_interval apart (RayBundle).
// OctoMap stays behind this interface (its headers are not part of lrd-slam's).
#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

#include "lrd/occupancy/occupancy_params.h"

namespace octomap {
class OcTreeKey;
}

namespace lrd::occupancy {

enum class VoxelState { Unknown, Free, Occupied };

// One keyframe's depth as rays: the camera centre and the measured points, in the map frame.
// Points with hit[i] == false only carve free space (seen through by other keyframes, so not a
// surface to keep); depth[i] is the measurement's z in its camera, for the noise model. How far a
// hit is believed: points before `trusted` make their voxel a surface at once; those before
// `measured` (the keyframe's own depth next to its dynamic pixels, where masks miss parts of
// people) count as one keyframe of min_hit_keyframes if min_hit_interval after the last one that
// counted; the rest (filled in from other keyframes by the background repair: not new
// measurements) add evidence but count as no keyframe.
struct RayBundle {
  double timestamp = 0.0;  // the keyframe's
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3f> points;
  std::vector<float> depth;
  std::vector<char> hit;
  std::size_t trusted = static_cast<std::size_t>(-1);  // all, unless set
  std::size_t measured = static_cast<std::size_t>(-1);
};

// What one keyframe's hit on a voxel tells (RayBundle).
enum class HitEvidence { Repaired, NearMask, Trusted };

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
  // One keyframe's hit on the voxel `key` (see RayBundle).
  void add_hit(const octomap::OcTreeKey& key, float log_odds_hit, HitEvidence evidence, double timestamp);
  OccupancyParams params_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace lrd::occupancy
