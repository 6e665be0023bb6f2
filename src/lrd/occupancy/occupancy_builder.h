#pragma once
// The occupancy outputs of a run, built from the dense stage's keyframe clouds at the keyframes'
// current poses: after a loop closure or global BA it is rebuilt from the stored keyframe views,
// so it follows the corrected poses. Runs in the caller's thread (the runner at the end of a run,
// the ROS publisher's thread while it runs), never in tracking's.
#include <filesystem>
#include <vector>

#include "lrd/dense/dense_mapper.h"
#include "lrd/occupancy/floor_frame.h"
#include "lrd/occupancy/grid_2d.h"
#include "lrd/occupancy/occupancy_map.h"
#include "lrd/occupancy/occupancy_params.h"

namespace lrd::occupancy {

// Each keyframe's cloud as rays from its camera centre, in the order the keyframes came.
[[nodiscard]] OccupancyMap build_occupancy_map(const std::vector<dense::DenseMapper::KeyframeCloud>& clouds,
                                               const OccupancyParams& params);

struct Occupancy {
  OccupancyMap map;
  FloorFrame floor;
  Grid2d grid;
};

// The map, its floor and the 2-D grid between params' heights.
[[nodiscard]] Occupancy build_occupancy(const std::vector<dense::DenseMapper::KeyframeCloud>& clouds,
                                        const OccupancyParams& params);

// OUT/occupancy.bt, OUT/occupancy_2d.pgm + .yaml (map_server), OUT/occupancy_2d.png (with the
// camera path, map-frame positions).
void write_occupancy(const Occupancy& occupancy, const OccupancyParams& params,
                     const std::vector<Eigen::Vector3d>& camera_path, const std::filesystem::path& out);

}  // namespace lrd::occupancy
