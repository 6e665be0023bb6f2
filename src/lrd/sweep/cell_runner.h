#pragma once
// One cell of a sweep: `lrdslam run` into a folder of its own beside the final one, its result
// written there, the folder renamed into place — so DIR/cells/ID exists only complete, and a
// killed run leaves nothing that counts. A failed run leaves DIR/cells/ID.failed.json with its
// one-line error instead.
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "lrd/sweep/sweep_plan.h"

namespace lrd::sweep {

enum class CellState { Missing, Done, Failed };

[[nodiscard]] CellState cell_state(const std::filesystem::path& dir, const SweepCell& cell);
[[nodiscard]] std::filesystem::path cell_folder(const std::filesystem::path& dir, const SweepCell& cell);
// The complete cell's DIR/cells/ID/result.json, or the failed cell's record; nullopt when missing.
[[nodiscard]] std::optional<nlohmann::json> cell_record(const std::filesystem::path& dir,
                                                        const SweepCell& cell);

// Where a run happened: the binary's version, the host, its CPU, the executor's job id.
struct Provenance {
  std::string version;  // `lrdslam --version`'s, with the git commit
  std::string host, cpu;
  unsigned cores = 0;
  std::string job_id;  // slurm:JOB_TASK or local:PID
};
[[nodiscard]] Provenance this_machine(const std::string& version);

// Runs `lrdslam run` (argv[0] the binary, then "run" and its arguments) with its output in `log`,
// and returns its exit code: in a child process (the default), or in the calling process (a Slurm
// task, which then starts one program instead of two).
using RunLauncher =
    std::function<int(const std::vector<std::string>& argv, const std::filesystem::path& log)>;
[[nodiscard]] int launch_child(const std::vector<std::string>& argv, const std::filesystem::path& log);

// Runs the cell with `binary` (an lrdslam), unless it is complete. Returns the state it ends in.
// The record holds the run's wall time and the sweep's own time around it (`overhead_seconds`).
CellState run_cell(const std::filesystem::path& dir, const SweepCell& cell,
                   const std::filesystem::path& binary, const Provenance& where,
                   const RunLauncher& launch = launch_child);

// The indices of the cells that are not complete (missing or failed), in order.
[[nodiscard]] std::vector<int> pending_cells(const std::filesystem::path& dir,
                                             const std::vector<SweepCell>& cells);

}  // namespace lrd::sweep
