#pragma once
// `lrdslam sweep collect DIR`: the cells' results as the paper's Tables 4-7 (ATE, RPE translation,
// RPE rotation: RMSE / mean / median / std) and Table 10 (time per frame, ms and Y), the
// improvement rate eta over `static`, each cell the median over its repeats with min, max and
// spread. Cells run by different binaries or configs are never pooled: they become rows of their
// own, marked with the version and config hash.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lrd/sweep/sweep_plan.h"

namespace lrd::sweep {

struct SweepTables {
  nlohmann::json results;  // DIR/results.json
  std::string markdown;    // DIR/tables.md
  std::size_t done = 0, failed = 0, missing = 0;
};

// Reads every cell's record (the manifest's order) and builds the tables.
[[nodiscard]] SweepTables collect_tables(const std::filesystem::path& dir,
                                         const std::vector<SweepCell>& cells);

// Writes DIR/results.json and DIR/tables.md (each beside, then renamed into place).
void write_tables(const std::filesystem::path& dir, const SweepTables& tables);

}  // namespace lrd::sweep
