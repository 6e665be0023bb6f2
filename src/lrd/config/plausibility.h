#pragma once
// Bounds a camera calibration and ORB settings must keep, whichever file they come from (ORB-SLAM
// settings or our YAML config): beyond them a value is a typo or garbage (NaN, 1e300, a negative
// count), and the run would go on with nonsense or fail far from the file that caused it.
#include <optional>
#include <string>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/features/orb_params.h"

namespace lrd::config {

// The first implausible field: its name as in our config ("fx", "k1", "depth_map_factor", ...)
// and what is wrong with it ("must be in (0, 100000]"). Empty when every field is plausible.
struct Implausible {
  std::string field;
  std::string problem;
};
[[nodiscard]] std::optional<Implausible> implausible_camera(const camera::PinholeCamera& camera);
// ... and of the ORB settings ("n_features", "scale_factor", "n_levels", "ini_th_fast", "min_th_fast").
[[nodiscard]] std::optional<Implausible> implausible_orb(const features::OrbParams& orb);

}  // namespace lrd::config
