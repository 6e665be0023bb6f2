#pragma once
// ORB extractor parameters, named after ORB-SLAM2's "ORBextractor.*" settings.
namespace lrd::features {

struct OrbParams {
  int n_features = 1000;      // features per image, spread over the pyramid
  float scale_factor = 1.2f;  // scale between pyramid levels (> 1)
  int n_levels = 8;           // pyramid levels
  int ini_th_fast = 20;       // FAST threshold tried first in each cell
  int min_th_fast = 7;        // fallback FAST threshold for low-contrast cells
};

}  // namespace lrd::features
