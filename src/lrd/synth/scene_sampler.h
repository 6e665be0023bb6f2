#pragma once
// scene.ply of the synthetic benchmark: points spread evenly over the static room's surfaces in
// world coordinates (with their texture colour), against which a dense map is judged: map points
// far from every sample are ghosts, samples the camera saw with no map point near are missing.
#include <cstdint>

#include "lrd/dense/point_cloud.h"
#include "lrd/synth/texture_library.h"
#include "lrd/synth/triangle_soup.h"

namespace lrd::synth {

// About one sample per spacing x spacing square metres of surface, uniformly at random within
// each triangle (deterministic for a seed); only triangles labelled static.
[[nodiscard]] dense::PointCloud sample_surfaces(const TriangleSoup& soup, const TextureLibrary& textures,
                                                double spacing = 0.02, std::uint64_t seed = 7);

}  // namespace lrd::synth
