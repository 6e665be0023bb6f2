#pragma once
// The 3-D map view of the run page (docs/report.md): the dense map (dense_map.ply), the sparse
// map's points (report_frames/sparse_map.ply, written by `run --report`) and the keyframes'
// positions (KeyFrameTrajectory.txt), as the page's three.js viewer reads them: positions as base64
// little-endian float32 triples, colours as base64 RGB bytes.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

namespace lrd::report {

// At most this many dense points go into a page (evenly strided): a few megabytes at most.
inline constexpr std::size_t kMaxDensePoints = 150000;

// Nothing when the run wrote neither map. Throws lrd::Error naming a PLY or trajectory file that
// does not parse.
[[nodiscard]] std::optional<nlohmann::json> map_view_data(const std::filesystem::path& run_dir);

}  // namespace lrd::report
