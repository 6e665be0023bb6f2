#pragma once
// A sweep's results.json (`lrdslam sweep collect`) in the benchmark page's shape: one run per
// sequence and mode with the medians over its repeats, every repeat's ATE RMSE for the page's
// distribution per cell, and the first complete repeat's folder for the trajectory plot.
#include <filesystem>
#include <nlohmann/json.hpp>

namespace lrd::report {

// True for a sweep's results (format lrdslam-sweep-results/1).
[[nodiscard]] bool is_sweep_results(const nlohmann::json& results);

// {"runs": [...], "presets": [...], "modes": [...], "repeats": true}; throws lrd::Error naming
// `file` for an entry without its sequence and mode.
[[nodiscard]] nlohmann::json sweep_as_benchmark(const nlohmann::json& results,
                                                const std::filesystem::path& file);

}  // namespace lrd::report
