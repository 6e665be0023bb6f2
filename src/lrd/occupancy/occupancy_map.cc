#include "lrd/occupancy/occupancy_map.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <octomap/OcTree.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <sstream>
#include <unordered_map>

#include "lrd/util/atomic_file.h"
#include "lrd/util/error.h"

namespace lrd::occupancy {

struct OccupancyMap::Tree {
  explicit Tree(const OccupancyParams& p) : tree(p.resolution) {
    tree.setProbHit(p.prob_hit);
    tree.setProbMiss(p.prob_miss);
    tree.setClampingThresMin(p.clamp_min);
    tree.setClampingThresMax(p.clamp_max);
  }
  octomap::OcTree tree;
  // Voxels some keyframe's rays ended in, by key: how many keyframes so far (up to
  // min_hit_keyframes) and the hits' log-odds not yet applied to the tree.
  struct Hits {
    int keyframes = 0;
    float pending = 0.0f;
    double counted_at = 0.0;  // the timestamp of the last keyframe counted
  };
  std::unordered_map<octomap::OcTreeKey, Hits, octomap::OcTreeKey::KeyHash> hits;
};

namespace {
octomap::point3d to_octomap(const Eigen::Vector3d& p) {
  return {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())};
}
Eigen::Vector3d to_eigen(const octomap::point3d& p) {
  return {p.x(), p.y(), p.z()};
}
// Sends stderr (file descriptor 2, where OctoMap's fprintf reports go) to /dev/null while it lives.
class QuietStderr {
 public:
  QuietStderr() : saved_(::dup(2)) {
    std::fflush(stderr);
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) {
      ::dup2(null, 2);
      ::close(null);
    }
  }
  ~QuietStderr() {
    std::fflush(stderr);
    if (saved_ >= 0) {
      ::dup2(saved_, 2);
      ::close(saved_);
    }
  }
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

 private:
  int saved_;
};

float log_odds(double p) {
  return static_cast<float>(std::log(p / (1.0 - p)));
}
}  // namespace

OccupancyMap::OccupancyMap(const OccupancyParams& params)
    : params_(params), tree_(std::make_unique<Tree>(params)) {}
OccupancyMap::~OccupancyMap() = default;
OccupancyMap::OccupancyMap(OccupancyMap&&) noexcept = default;
OccupancyMap& OccupancyMap::operator=(OccupancyMap&&) noexcept = default;

double OccupancyMap::resolution() const {
  return tree_->tree.getResolution();
}

float OccupancyMap::hit_log_odds(const OccupancyParams& p, double z) {
  const double sigma = p.depth_noise * z * z;
  const double inside = sigma <= 0.0 ? 1.0 : std::erf(p.resolution / (2.0 * std::sqrt(2.0) * sigma));
  return log_odds(0.5 + (p.prob_hit - 0.5) * inside);
}

void OccupancyMap::integrate(const RayBundle& rays) {
  octomap::OcTree& tree = tree_->tree;
  const octomap::point3d origin = to_octomap(rays.origin);
  // Each ray's end voxel once (rays ending in one voxel share their path up to the resolution,
  // as OctoMap's discretized insertion): its smallest depth (the most certain hit), whether any
  // ray ends there on a surface, and its centre (or the cut point of a ray longer than max_range).
  struct End {
    float depth;
    bool hit;
    HitEvidence evidence;  // the best of the hits ending here
  };
  std::unordered_map<octomap::OcTreeKey, End, octomap::OcTreeKey::KeyHash> ends;
  const float max_range = static_cast<float>(params_.max_range);
  for (std::size_t i = 0; i < rays.points.size(); ++i) {
    const Eigen::Vector3f& p = rays.points[i];
    if (!p.allFinite()) continue;
    const Eigen::Vector3f d = p - rays.origin.cast<float>();
    const float z = rays.depth[i];
    if (!(z > 0.0f) || !(d.squaredNorm() > 0.0f)) continue;
    bool hit = rays.hit[i] != 0;
    Eigen::Vector3f end = p;
    if (z > max_range) {  // cut where its depth reaches max_range: free up to there, no surface
      end = rays.origin.cast<float>() + d * (max_range / z);
      hit = false;
    }
    octomap::OcTreeKey key;
    if (!tree.coordToKeyChecked(octomap::point3d(end.x(), end.y(), end.z()), key)) continue;
    const HitEvidence evidence = !hit                ? HitEvidence::Repaired
                                 : i < rays.trusted  ? HitEvidence::Trusted
                                 : i < rays.measured ? HitEvidence::NearMask
                                                     : HitEvidence::Repaired;
    auto [it, fresh] = ends.try_emplace(key, End{rays.depth[i], hit, evidence});
    if (!fresh) {
      it->second.depth = std::min(it->second.depth, rays.depth[i]);
      it->second.hit = it->second.hit || hit;
      it->second.evidence = std::max(it->second.evidence, evidence);
    }
  }
  octomap::KeySet free;
  octomap::KeyRay ray;
  for (const auto& [key, end] : ends) {
    if (tree.computeRayKeys(origin, tree.keyToCoord(key), ray)) free.insert(ray.begin(), ray.end());
    if (!end.hit) free.insert(key);  // seen through: the end voxel is free too
  }
  // A voxel another ray ends on stays a surface.
  const float miss = log_odds(params_.prob_miss);
  for (const octomap::OcTreeKey& key : free) {
    const auto e = ends.find(key);
    if (e == ends.end() || !e->second.hit) tree.updateNode(key, miss, true);
  }
  for (const auto& [key, end] : ends)
    if (end.hit) add_hit(key, hit_log_odds(params_, end.depth), end.evidence, rays.timestamp);
  tree.updateInnerOccupancy();
}

void OccupancyMap::add_hit(const octomap::OcTreeKey& key, float log_odds_hit, HitEvidence evidence,
                           double timestamp) {
  Tree::Hits& h = tree_->hits[key];
  if (evidence == HitEvidence::Trusted) h.keyframes = params_.min_hit_keyframes;
  if (h.keyframes >= params_.min_hit_keyframes) {
    tree_->tree.updateNode(key, h.pending + log_odds_hit, true);
    h.pending = 0.0f;
    return;
  }
  h.pending += log_odds_hit;
  // A repaired pixel is an earlier keyframe's measurement seen again: a part of a walker the mask
  // missed there, copied into the next keyframes' repairs, must not confirm itself.
  if (evidence == HitEvidence::Repaired) return;
  // Keyframes a moment apart (a person filling the view makes tracking add several within half
  // a second) see a walker in the same place: only keyframes min_hit_interval apart count.
  if (h.keyframes > 0 && std::abs(timestamp - h.counted_at) < params_.min_hit_interval) return;
  h.counted_at = timestamp;
  if (++h.keyframes < params_.min_hit_keyframes) return;
  tree_->tree.updateNode(key, h.pending, true);  // confirmed: every hit so far counts
  h.pending = 0.0f;
}

VoxelState OccupancyMap::state_at(const Eigen::Vector3d& p) const {
  const octomap::OcTreeNode* node = tree_->tree.search(to_octomap(p));
  if (node == nullptr) return VoxelState::Unknown;
  return tree_->tree.isNodeOccupied(node) ? VoxelState::Occupied : VoxelState::Free;
}

bool OccupancyMap::has_occupied_neighbour(const Eigen::Vector3d& p) const {
  const double res = resolution();
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz)
        if ((dx != 0 || dy != 0 || dz != 0) &&
            state_at(p + Eigen::Vector3d(dx, dy, dz) * res) == VoxelState::Occupied)
          return true;
  return false;
}

void OccupancyMap::visit(const std::function<void(const Eigen::Vector3d&, bool)>& fn) const {
  const octomap::OcTree& tree = tree_->tree;
  const double res = tree.getResolution();
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    const bool occupied = tree.isNodeOccupied(*it);
    const double size = it.getSize();
    const int n = std::max(1, static_cast<int>(std::lround(size / res)));  // a pruned leaf: n^3 voxels
    const Eigen::Vector3d corner = to_eigen(it.getCoordinate()) - Eigen::Vector3d::Constant(size / 2.0);
    for (int x = 0; x < n; ++x)
      for (int y = 0; y < n; ++y)
        for (int z = 0; z < n; ++z)
          fn(corner + (Eigen::Vector3d(x, y, z) + Eigen::Vector3d::Constant(0.5)) * res, occupied);
  }
}

std::vector<Eigen::Vector3d> OccupancyMap::occupied_voxels() const {
  std::vector<Eigen::Vector3d> out;
  visit([&out](const Eigen::Vector3d& centre, bool occupied) {
    if (occupied) out.push_back(centre);
  });
  return out;
}

std::size_t OccupancyMap::count(VoxelState state) const {
  std::size_t n = 0;
  visit([&n, state](const Eigen::Vector3d&, bool occupied) {
    n += (occupied ? VoxelState::Occupied : VoxelState::Free) == state;
  });
  return n;
}

void OccupancyMap::write_binary(const std::filesystem::path& file) const {
  util::AtomicFile out(file);
  // The const writer: the tree is not pruned or thresholded in place. It reports "Writing N nodes
  // ... done." with fprintf on stderr; that goes to /dev/null meanwhile (after the run, or at the
  // node's stop: another thread's log line in these milliseconds would be lost too).
  bool ok = false;
  {
    const QuietStderr quiet;
    ok = tree_->tree.writeBinaryConst(out.stream());
  }
  // A failed write of the stream is reported by commit() with its reason.
  if (!ok && out.stream().good()) throw file_error(file, "cannot write");
  out.commit();
}

OccupancyMap OccupancyMap::read_binary(const std::filesystem::path& file, const OccupancyParams& params) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw file_error(file, "cannot read");
  // The header (as OcTree::readBinary reads it, which reports on stderr: ours is one line).
  std::string line;
  std::getline(in, line);
  if (line.rfind("# Octomap OcTree binary file", 0) != 0)
    throw file_error(file, "not an OctoMap binary file (.bt)");
  std::string id;
  std::size_t size = 0;
  double res = 0.0;
  bool data = false;
  while (!data && std::getline(in, line)) {
    std::istringstream fields(line);
    std::string key;
    fields >> key;
    if (key == "id")
      fields >> id;
    else if (key == "size")
      fields >> size;
    else if (key == "res")
      fields >> res;
    data = key == "data";
  }
  if (!data) throw file_error(file, "corrupt OctoMap binary file: no data");
  if (id != "OcTree") throw file_error(file, "holds an OctoMap '" + id + "', not an OcTree");
  if (!(res > 0.0)) throw file_error(file, "corrupt OctoMap binary file: no resolution");
  OccupancyParams p = params;
  p.resolution = res;
  OccupancyMap map(p);
  map.tree_->tree.readBinaryData(in);
  if (map.tree_->tree.size() != size)
    throw file_error(file, fmt::format("corrupt OctoMap binary file: {} nodes read, the header says {}",
                                       map.tree_->tree.size(), size));
  return map;
}

}  // namespace lrd::occupancy
