#include "lrd/sweep/executors.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"
#include "lrd/util/process.h"

namespace lrd::sweep {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// sbatch --parsable prints "JOBID" or "JOBID;CLUSTER".
std::string sbatch(std::vector<std::string> argv) {
  argv.insert(argv.begin(), {"sbatch", "--parsable"});
  const util::ProcessResult r = util::run_process(argv);
  std::string id = r.output.substr(0, r.output.find_first_of(";\n"));
  if (r.exit_code != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos)
    throw Error(fmt::format(
        "sweep: sbatch failed (exit {}){}", r.exit_code,
        r.output.empty() ? std::string() : fmt::format(": {}", r.output.substr(0, r.output.find('\n')))));
  return id;
}

// "0-3,7,9-10": Slurm's array index list.
std::string index_list(const std::vector<int>& indices) {
  std::string out;
  for (std::size_t i = 0; i < indices.size();) {
    std::size_t j = i;
    while (j + 1 < indices.size() && indices[j + 1] == indices[j] + 1) ++j;
    out += (out.empty() ? "" : ",") +
           (j == i ? std::to_string(indices[i]) : fmt::format("{}-{}", indices[i], indices[j]));
    i = j + 1;
  }
  return out;
}

json read_jobs(const fs::path& dir) {
  const fs::path file = dir / "slurm" / "jobs.json";
  std::error_code ec;
  if (!fs::exists(file, ec)) return json::array();
  try {
    return json::parse(util::read_file_bytes(file, "Slurm job list"));
  } catch (const json::exception& e) {
    throw file_error(file, std::string("not JSON: ") + e.what());
  }
}

std::vector<std::string> job_ids(const json& jobs) {
  std::vector<std::string> ids;
  for (const json& j : jobs) {
    ids.push_back(j.value("array_job", ""));
    ids.push_back(j.value("collect_job", ""));
  }
  ids.erase(std::remove(ids.begin(), ids.end(), std::string()), ids.end());
  return ids;
}

void progress_line(const fs::path& dir, const std::vector<SweepCell>& cells, const std::string& tail) {
  std::size_t done = 0, failed = 0;
  for (const SweepCell& c : cells) {
    const CellState s = cell_state(dir, c);
    done += s == CellState::Done;
    failed += s == CellState::Failed;
  }
  std::fprintf(stderr, "\rsweep: %zu/%zu cells done, %zu failed%s   ", done, cells.size(), failed,
               tail.c_str());
  std::fflush(stderr);
}

}  // namespace

void require_program(const std::string& program, const std::string& what) {
  if (!util::find_on_path(program))
    throw Error(fmt::format("sweep: {} needs {} on PATH (Slurm's client: apt-get install slurm-client)", what,
                            program));
}

int default_jobs() {
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()) / 2);
}

void run_local(const fs::path& dir, const std::vector<SweepCell>& cells, const std::vector<int>& indices,
               const fs::path& binary, int jobs, const Provenance& where, bool progress) {
  std::atomic<std::size_t> next{0};
  std::mutex output;
  std::exception_ptr error;
  const auto worker = [&] {
    for (std::size_t k = next++; k < indices.size(); k = next++) {
      try {
        (void)run_cell(dir, cells.at(static_cast<std::size_t>(indices[k])), binary, where);
      } catch (...) {
        std::lock_guard lock(output);
        if (!error) error = std::current_exception();
        next = indices.size();  // a broken sweep folder stops every worker
      }
      if (progress) {
        std::lock_guard lock(output);
        progress_line(dir, cells, "");
      }
    }
  };
  std::vector<std::thread> threads;
  for (int j = 0; j < std::max(1, jobs); ++j) threads.emplace_back(worker);
  for (std::thread& t : threads) t.join();
  if (progress) std::fputc('\n', stderr);
  if (error) std::rethrow_exception(error);
}

SlurmSubmission submit_slurm(const fs::path& dir, const std::vector<int>& indices, const fs::path& binary,
                             const SlurmOptions& o) {
  require_program("sbatch", "--executor slurm");
  const fs::path abs = fs::absolute(dir).lexically_normal();
  std::error_code ec;
  fs::create_directories(abs / "slurm", ec);
  fs::create_directories(abs / "logs", ec);
  const fs::path script = abs / "slurm" / "sweep.sh";
  util::write_file_bytes(
      script, fmt::format("#!/bin/sh\n# One cell of the sweep per array task.\nexec {} sweep run-cell {} "
                          "\"$SLURM_ARRAY_TASK_ID\"\n",
                          shell_quote(binary.string()), shell_quote(abs.string())));
  fs::permissions(script, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                  fs::perm_options::add);
  std::string array = index_list(indices);
  if (o.max_running > 0) array += fmt::format("%{}", o.max_running);
  std::vector<std::string> args{"--array=" + array, fmt::format("--cpus-per-task={}", o.cpus_per_task),
                                "--job-name=lrdslam-sweep",
                                "--output=" + (abs / "logs" / "slurm-%A_%a.out").string()};
  args.insert(args.end(), o.extra_args.begin(), o.extra_args.end());
  args.push_back(script.string());
  SlurmSubmission s;
  s.array_job = sbatch(args);
  std::vector<std::string> collect{
      fmt::format("--dependency=afterany:{}", s.array_job), "--job-name=lrdslam-collect",
      fmt::format("--output={}", (abs / "logs" / "slurm-collect-%j.out").string())};
  collect.insert(collect.end(), o.extra_args.begin(), o.extra_args.end());
  collect.push_back(
      fmt::format("--wrap={} sweep collect {}", shell_quote(binary.string()), shell_quote(abs.string())));
  s.collect_job = sbatch(collect);
  json jobs = read_jobs(abs);
  jobs.push_back({{"array_job", s.array_job}, {"collect_job", s.collect_job}, {"indices", indices}});
  util::write_file_bytes(abs / "slurm" / "jobs.json", jobs.dump(1) + "\n");
  return s;
}

std::size_t slurm_jobs_queued(const fs::path& dir) {
  const std::vector<std::string> ids = job_ids(read_jobs(dir));
  if (ids.empty() || !util::find_on_path("squeue")) return 0;
  std::string list;
  for (const std::string& id : ids) list += (list.empty() ? "" : ",") + id;
  // Jobs Slurm has forgotten make squeue fail ("Invalid job id"): none of them is queued then.
  const util::ProcessResult r = util::run_process({"squeue", "-h", "-r", "-j", list, "-o", "%T"});
  if (r.exit_code != 0) return 0;
  std::size_t queued = 0;
  std::size_t start = 0;
  while (start < r.output.size()) {
    const std::size_t end = std::min(r.output.find('\n', start), r.output.size());
    const std::string state = r.output.substr(start, end - start);
    queued += state == "PENDING" || state == "RUNNING" || state == "CONFIGURING" || state == "COMPLETING" ||
              state == "SUSPENDED" || state == "REQUEUED";
    start = end + 1;
  }
  return queued;
}

void wait_for_slurm(const fs::path& dir, const std::vector<SweepCell>& cells) {
  require_program("squeue", "--wait");
  while (true) {
    const std::size_t queued = slurm_jobs_queued(dir);
    progress_line(dir, cells, fmt::format(", {} Slurm job(s) queued or running", queued));
    if (queued == 0) break;
    std::this_thread::sleep_for(std::chrono::seconds(2));
  }
  std::fputc('\n', stderr);
}

void cancel_slurm(const fs::path& dir) {
  const std::vector<std::string> ids = job_ids(read_jobs(dir));
  if (ids.empty()) throw Error(fmt::format("sweep cancel: {} has no Slurm jobs recorded", dir.string()));
  require_program("scancel", "sweep cancel");
  std::vector<std::string> argv{"scancel"};
  argv.insert(argv.end(), ids.begin(), ids.end());
  const util::ProcessResult r = util::run_process(argv);
  if (r.exit_code != 0) throw Error(fmt::format("sweep cancel: scancel failed (exit {})", r.exit_code));
}

}  // namespace lrd::sweep
