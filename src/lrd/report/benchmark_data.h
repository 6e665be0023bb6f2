#pragma once
// What the benchmark page shows (docs/report.md): bench_dynamic's results.json — the paper's
// Tables 4-7 and 10, the improvement rate eta, the dynamic flags — and per preset every mode's
// trajectory aligned onto the ground truth, read from the runs the benchmark wrote
// (runs/PRESET/MODE/).
#include <filesystem>
#include <nlohmann/json.hpp>

namespace lrd::report {

// True when `dir` holds a benchmark's results.json (and no run's summary.json).
[[nodiscard]] bool is_benchmark_folder(const std::filesystem::path& dir);

// Throws lrd::Error naming the file for a results.json that does not parse or has no "runs"
// list, a run entry without "preset" and "mode", or a run's trajectory or ground truth that does
// not parse. A run folder without a trajectory is shown in the tables only.
[[nodiscard]] nlohmann::json collect_benchmark_data(const std::filesystem::path& bench_dir);

}  // namespace lrd::report
