#pragma once
// Where a sweep's cells run: here, N at a time (`--executor local`), or on a Slurm cluster as one
// job array (`--executor slurm`). Slurm is not linked: its client commands are called.
#include <filesystem>
#include <string>
#include <vector>

#include "lrd/sweep/cell_runner.h"
#include "lrd/sweep/sweep_plan.h"

namespace lrd::sweep {

// Runs the cells `indices` with `jobs` runs at a time; a progress line on stderr when `progress`.
void run_local(const std::filesystem::path& dir, const std::vector<SweepCell>& cells,
               const std::vector<int>& indices, const std::filesystem::path& binary, int jobs,
               const Provenance& where, bool progress);

// Runs at once that keep every core busy without oversubscribing: a run keeps about two busy
// (tracking and local mapping; the segmentation network and the dense map share them).
[[nodiscard]] int default_jobs();

struct SlurmOptions {
  int cpus_per_task = 2;
  int max_running = 0;                  // the array's %K (0: Slurm's own limit)
  std::vector<std::string> extra_args;  // --slurm-arg, given to sbatch as they are
};

struct SlurmSubmission {
  std::string array_job, collect_job;
};

// One job array over `indices` (DIR/slurm/sweep.sh runs `lrdslam sweep run-cell DIR
// $SLURM_ARRAY_TASK_ID`, logs in DIR/logs/slurm-JOB_TASK.out) and a collect job after it
// (--dependency=afterany). Recorded in DIR/slurm/jobs.json. Throws lrd::Error naming the missing
// command, or sbatch's own one-line error.
[[nodiscard]] SlurmSubmission submit_slurm(const std::filesystem::path& dir, const std::vector<int>& indices,
                                           const std::filesystem::path& binary, const SlurmOptions& options);

// The sweep's recorded jobs that Slurm still lists as pending or running (squeue).
[[nodiscard]] std::size_t slurm_jobs_queued(const std::filesystem::path& dir);

// Follows the queue until the sweep's jobs are gone, with a progress line on stderr.
void wait_for_slurm(const std::filesystem::path& dir, const std::vector<SweepCell>& cells);

// scancel for every recorded job of the sweep.
void cancel_slurm(const std::filesystem::path& dir);

// Throws "sweep: ... needs PROGRAM on PATH" when it is not there.
void require_program(const std::string& program, const std::string& what);

}  // namespace lrd::sweep
