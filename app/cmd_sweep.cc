// `lrdslam sweep`: the paper's experiment over folders, bags and synthetic presets x modes x
// config variants x repeats, each cell one `lrdslam run`, on this machine or a Slurm cluster;
// `sweep status DIR`, `sweep collect DIR`, `sweep cancel DIR` (docs/sweep.md).
#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "app/commands.h"
#include "lrd/sweep/cell_runner.h"
#include "lrd/sweep/executors.h"
#include "lrd/sweep/sweep_plan.h"
#include "lrd/sweep/sweep_tables.h"
#include "lrd/util/error.h"
#include "lrd/util/process.h"
#include "lrd_git_commit.h"

namespace lrd::app {
namespace {

namespace fs = std::filesystem;

struct SweepCli {
  std::string out;
  std::vector<std::string> sequences, presets, modes, variants, sets, run_args, slurm_args;
  std::vector<int> seeds{1};
  int frames = -1, repeats = 1, jobs = 0, cpus_per_task = 2, max_running = 0;
  std::string realism = "clean", executor = "local", segmenter;
  bool deterministic = false, wait = false;
  std::string dir;  // status / collect / cancel / run-cell
  int index = -1;
};

std::string version_string() {
  return std::string(LRD_VERSION) + " (" + LRD_GIT_COMMIT + ")";
}

sweep::SweepSpec spec_of(const SweepCli& c) {
  sweep::SweepSpec s;
  for (const std::string& q : c.sequences) s.sequences.emplace_back(q);
  s.presets = c.presets;
  s.seeds = c.seeds;
  s.frames = c.frames;
  s.realism = c.realism;
  s.modes = c.modes;
  s.repeats = c.repeats;
  s.deterministic = c.deterministic;
  s.segmenter = c.segmenter;
  s.sets = c.sets;
  s.run_args = c.run_args;
  for (const std::string& v : c.variants) {
    const std::size_t eq = v.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == v.size() || v.substr(0, eq) == "default")
      throw Error("sweep: --config-variant " + v + ": expected NAME=FILE (NAME not 'default')");
    s.variants[v.substr(0, eq)] = v.substr(eq + 1);
  }
  return s;
}

void print_collect(const fs::path& dir, const std::vector<sweep::SweepCell>& cells) {
  const sweep::SweepTables t = sweep::collect_tables(dir, cells);
  sweep::write_tables(dir, t);
  std::fputs(t.markdown.c_str(), stdout);
  std::printf("wrote %s and %s\n", (dir / "results.json").c_str(), (dir / "tables.md").c_str());
}

// The sweep's own time per cell against the runs' (the bar: under 1 %): planning and collecting
// spread over the cells run, plus each cell's bookkeeping around its run.
void print_overhead(const fs::path& dir, const std::vector<sweep::SweepCell>& cells,
                    const std::vector<int>& ran, double planning_and_collection) {
  std::vector<double> runs;
  double bookkeeping = 0.0;
  for (int i : ran) {
    const auto record = sweep::cell_record(dir, cells[static_cast<std::size_t>(i)]);
    if (!record || !record->contains("overhead_seconds")) continue;
    runs.push_back((*record)["wall_seconds"].get<double>());
    bookkeeping += (*record)["overhead_seconds"].get<double>();
  }
  if (runs.empty()) return;
  std::sort(runs.begin(), runs.end());
  const double per_cell = (planning_and_collection + bookkeeping) / static_cast<double>(runs.size());
  const double median = runs[runs.size() / 2];
  std::printf(
      "sweep overhead: %.1f ms per cell (planning, bookkeeping, collection) = %.2f %% of the median run "
      "(%.2f s)\n",
      1e3 * per_cell, 100.0 * per_cell / median, median);
}

void run_sweep(const SweepCli& c) {
  if (c.out.empty()) throw Error("sweep: give --out DIR (or a subcommand: status, collect, cancel)");
  if (c.executor != "local" && c.executor != "slurm")
    throw Error("sweep: --executor must be local or slurm, got '" + c.executor + "'");
  if (c.executor == "slurm") sweep::require_program("sbatch", "--executor slurm");
  if (c.executor == "slurm" && c.wait) sweep::require_program("squeue", "--wait");
  const auto t0 = std::chrono::steady_clock::now();
  const fs::path dir = c.out;
  const sweep::SweepPlan plan = sweep::plan_sweep(spec_of(c));  // every argument checked here
  sweep::write_manifest(dir, plan);
  const std::vector<int> pending = sweep::pending_cells(dir, plan.cells);
  std::printf("sweep %s: %zu cells, %zu to run\n", dir.c_str(), plan.cells.size(), pending.size());
  std::fflush(stdout);
  const fs::path binary = util::own_executable();
  if (c.executor == "local") {
    const double planning = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!pending.empty())
      sweep::run_local(dir, plan.cells, pending, binary, c.jobs > 0 ? c.jobs : sweep::default_jobs(),
                       sweep::this_machine(version_string()), true);
    const auto t1 = std::chrono::steady_clock::now();
    print_collect(dir, plan.cells);
    const double collection = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    print_overhead(dir, plan.cells, pending, planning + collection);
    return;
  }
  if (pending.empty()) {
    print_collect(dir, plan.cells);
    return;
  }
  const sweep::SlurmSubmission s =
      sweep::submit_slurm(dir, pending, binary, {c.cpus_per_task, c.max_running, c.slurm_args});
  std::printf("submitted job array %s (%zu tasks) and collect job %s\n", s.array_job.c_str(), pending.size(),
              s.collect_job.c_str());
  std::fflush(stdout);
  if (c.wait) {
    sweep::wait_for_slurm(dir, plan.cells);
    print_collect(dir, plan.cells);
  }
}

void print_status(const fs::path& dir) {
  const std::vector<sweep::SweepCell> cells = sweep::read_manifest(dir);
  std::size_t done = 0, failed = 0;
  std::vector<std::string> missing, failures;
  for (const sweep::SweepCell& cell : cells) {
    switch (sweep::cell_state(dir, cell)) {
      case sweep::CellState::Done:
        ++done;
        break;
      case sweep::CellState::Failed:
        ++failed;
        failures.push_back(cell.id + ": " + sweep::cell_record(dir, cell)->value("error", "failed"));
        break;
      case sweep::CellState::Missing:
        missing.push_back(cell.id);
        break;
    }
  }
  std::printf("sweep %s: %zu cells: %zu done, %zu failed, %zu missing", dir.c_str(), cells.size(), done,
              failed, missing.size());
  const std::size_t queued = sweep::slurm_jobs_queued(dir);
  if (queued > 0) std::printf(", %zu Slurm job(s) queued or running", queued);
  std::printf("\n");
  for (const std::string& f : failures) std::printf("failed: %s\n", f.c_str());
  for (const std::string& m : missing) std::printf("missing: %s\n", m.c_str());
}

// `lrdslam run` in this process with stdout and stderr in `log`: a Slurm task starts one program
// (loading OpenCV's ~180 shared libraries takes 0.15-0.2 s here), not two.
int run_in_process(const std::vector<std::string>& argv, const fs::path& log) {
  CLI::App app{"lrdslam", "lrdslam"};
  register_run_command(app);
  std::vector<const char*> args;
  for (const std::string& a : argv) args.push_back(a.c_str());
  std::fflush(stdout);
  std::fflush(stderr);
  const int saved_out = dup(STDOUT_FILENO), saved_err = dup(STDERR_FILENO);
  const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  if (fd < 0 || saved_out < 0 || saved_err < 0) throw file_error(log, "cannot open the run's log");
  dup2(fd, STDOUT_FILENO);
  dup2(fd, STDERR_FILENO);
  close(fd);
  int code = 0;
  try {
    app.parse(static_cast<int>(args.size()), args.data());
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "error: %s (see --help)\n", e.what());
    code = e.get_exit_code() == 0 ? 1 : e.get_exit_code();
  } catch (const cv::Exception& e) {
    std::fprintf(stderr, "error: OpenCV: %s\n", e.err.c_str());
    code = 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    code = 1;
  }
  std::fflush(stdout);
  std::fflush(stderr);
  dup2(saved_out, STDOUT_FILENO);
  dup2(saved_err, STDERR_FILENO);
  close(saved_out);
  close(saved_err);
  return code;
}

void run_one_cell(const fs::path& dir, int index) {
  const std::vector<sweep::SweepCell> cells = sweep::read_manifest(dir);
  if (index < 0 || index >= static_cast<int>(cells.size()))
    throw Error(
        fmt::format("sweep run-cell: {} has cells 0-{}, not {}", dir.string(), cells.size() - 1, index));
  const sweep::SweepCell& cell = cells[static_cast<std::size_t>(index)];
  const sweep::CellState s = sweep::run_cell(dir, cell, util::own_executable(),
                                             sweep::this_machine(version_string()), run_in_process);
  if (s == sweep::CellState::Failed)
    throw Error("sweep: cell " + cell.id + " failed: " + sweep::cell_record(dir, cell)->value("error", ""));
}

void add_grid_options(CLI::App* cmd, SweepCli& c) {
  cmd->add_option("--out", c.out, "The sweep's folder (created; the same command again resumes it)");
  cmd->add_option("--sequences", c.sequences, "TUM-layout folders and bags, comma-separated")->delimiter(',');
  cmd->add_option("--presets", c.presets, "Synthetic presets, comma-separated (lrdslam synth --list)")
      ->delimiter(',');
  cmd->add_option("--seeds", c.seeds, "With --presets: seeds, comma-separated")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--frames", c.frames, "With --presets: a prefix of N frames");
  cmd->add_option("--realism", c.realism, "With --presets: clean or tum")->capture_default_str();
  cmd->add_option("--modes", c.modes, "static, semantic, geometric, full; comma-separated")->delimiter(',');
  cmd->add_option("--repeats", c.repeats, "Runs per cell (the tables take their median)")
      ->capture_default_str();
  cmd->add_flag("--deterministic", c.deterministic, "Every run in --deterministic mode");
  cmd->add_option("--segmenter", c.segmenter, "Every run's --segmenter (default: each run's own)");
  cmd->add_option("--config-variant", c.variants,
                  "NAME=FILE: a config to run every cell with too (repeatable)");
  cmd->add_option("--set", c.sets,
                  "KEY=VALUE in every variant's config, e.g. tracking.keyframe_close_tracked=50");
  cmd->add_option("--run-arg", c.run_args,
                  "An `lrdslam run` argument for every run, as --run-arg=--dense (repeatable, in order)");
}

}  // namespace

void register_sweep_command(CLI::App& app) {
  auto cli = std::make_shared<SweepCli>();
  auto* cmd = app.add_subcommand("sweep",
                                 "Run the paper's experiment: inputs x modes x variants x repeats, "
                                 "here or on Slurm, and its tables (docs/sweep.md)");
  add_grid_options(cmd, *cli);
  cmd->add_option("--executor", cli->executor, "local (this machine) or slurm (one job array)")
      ->capture_default_str();
  cmd->add_option("--jobs", cli->jobs, "local: runs at once (default: cores / 2, no oversubscription)");
  cmd->add_flag("--wait", cli->wait, "slurm: follow the queue until the sweep is done, then collect");
  cmd->add_option("--cpus-per-task", cli->cpus_per_task, "slurm: CPUs per run")->capture_default_str();
  cmd->add_option("--max-running", cli->max_running, "slurm: at most K array tasks at once (%K)");
  cmd->add_option("--slurm-arg", cli->slurm_args,
                  "slurm: an sbatch argument, as --slurm-arg=--partition=cpu");
  cmd->require_subcommand(0, 1);
  auto* status = cmd->add_subcommand("status", "Cells done, failed (with their errors) and missing");
  status->add_option("dir", cli->dir, "The sweep's folder")->required();
  auto* collect =
      cmd->add_subcommand("collect", "Tables 4-7 and 10, eta, DIR/results.json and DIR/tables.md");
  collect->add_option("dir", cli->dir, "The sweep's folder")->required();
  auto* cancel = cmd->add_subcommand("cancel", "scancel the sweep's Slurm jobs");
  cancel->add_option("dir", cli->dir, "The sweep's folder")->required();
  auto* cell = cmd->add_subcommand("run-cell", "Run one cell (what each Slurm array task does)");
  cell->add_option("dir", cli->dir, "The sweep's folder")->required();
  cell->add_option("index", cli->index, "The cell's index in manifest.json")->required();
  status->callback([cli] { print_status(cli->dir); });
  collect->callback([cli] { print_collect(cli->dir, sweep::read_manifest(cli->dir)); });
  cancel->callback([cli] { sweep::cancel_slurm(cli->dir); });
  cell->callback([cli] { run_one_cell(cli->dir, cli->index); });
  cmd->callback([cmd, cli] {
    if (cmd->get_subcommands().empty()) run_sweep(*cli);
  });
}

}  // namespace lrd::app
