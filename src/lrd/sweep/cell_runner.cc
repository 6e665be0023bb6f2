#include "lrd/sweep/cell_runner.h"

#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"
#include "lrd/util/process.h"

namespace lrd::sweep {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

fs::path failed_file(const fs::path& dir, const SweepCell& cell) {
  return dir / "cells" / (cell.id + ".failed.json");
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos)
      return line.substr(line.find(':') + 2);
  return "unknown";
}

// The last non-empty line of a run's log: its one-line error.
std::string last_line(const fs::path& log) {
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  return last.empty() ? "no output" : last;
}

// The cell's arguments with the sweep's own files (configs/) named from anywhere.
std::vector<std::string> run_argv(const fs::path& dir, const SweepCell& cell, const fs::path& binary,
                                  const fs::path& out) {
  std::vector<std::string> argv{binary.string(), "run"};
  for (std::size_t i = 0; i < cell.args.size(); ++i) {
    const bool config = i > 0 && cell.args[i - 1] == "--config" && cell.args[i].rfind("configs/", 0) == 0;
    argv.push_back(config ? (fs::absolute(dir) / cell.args[i]).string() : cell.args[i]);
  }
  argv.insert(argv.end(), {"--out", out.string()});
  return argv;
}

std::string config_hash(const fs::path& dir, const SweepCell& cell) {
  for (std::size_t i = 1; i < cell.args.size(); ++i)
    if (cell.args[i - 1] == "--config") {
      const fs::path file =
          cell.args[i].rfind("configs/", 0) == 0 ? dir / cell.args[i] : fs::path(cell.args[i]);
      return content_hash(util::read_file_bytes(file, "config"));
    }
  return content_hash("");
}

json read_json(const fs::path& file) {
  try {
    return json::parse(util::read_file_bytes(file, "result"));
  } catch (const json::exception& e) {
    throw file_error(file, std::string("not JSON: ") + e.what());
  }
}

}  // namespace

fs::path cell_folder(const fs::path& dir, const SweepCell& cell) {
  return dir / "cells" / cell.id;
}

CellState cell_state(const fs::path& dir, const SweepCell& cell) {
  std::error_code ec;
  if (fs::exists(cell_folder(dir, cell) / "result.json", ec)) return CellState::Done;
  if (fs::exists(failed_file(dir, cell), ec)) return CellState::Failed;
  return CellState::Missing;
}

std::optional<json> cell_record(const fs::path& dir, const SweepCell& cell) {
  switch (cell_state(dir, cell)) {
    case CellState::Done:
      return read_json(cell_folder(dir, cell) / "result.json");
    case CellState::Failed:
      return read_json(failed_file(dir, cell));
    case CellState::Missing:
      break;
  }
  return std::nullopt;
}

Provenance this_machine(const std::string& version) {
  Provenance p;
  p.version = version;
  char host[256] = {};
  p.host = gethostname(host, sizeof host - 1) == 0 ? host : "unknown";
  p.cpu = cpu_model();
  p.cores = std::thread::hardware_concurrency();
  const char* job = std::getenv("SLURM_ARRAY_JOB_ID");
  const char* task = std::getenv("SLURM_ARRAY_TASK_ID");
  p.job_id = job != nullptr && task != nullptr ? fmt::format("slurm:{}_{}", job, task)
                                               : fmt::format("local:{}", static_cast<long>(getpid()));
  return p;
}

int launch_child(const std::vector<std::string>& argv, const fs::path& log) {
  return util::run_process(argv, log).exit_code;
}

CellState run_cell(const fs::path& dir, const SweepCell& cell, const fs::path& binary,
                   const Provenance& where, const RunLauncher& launch) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  if (cell_state(dir, cell) == CellState::Done) return CellState::Done;
  std::error_code ec;
  fs::create_directories(dir / "cells", ec);
  fs::create_directories(dir / "logs", ec);
  // Beside the final folder, named by this process: two executors never share one.
  const fs::path partial =
      dir / "cells" / fmt::format(".{}.partial-{}", cell.id, static_cast<long>(getpid()));
  const fs::path log = dir / "logs" / (cell.id + ".log");
  fs::remove_all(partial, ec);
  fs::remove(log, ec);
  const auto t0 = Clock::now();
  const int exit_code = launch(run_argv(dir, cell, binary, partial), log);
  const auto t1 = Clock::now();
  const double seconds = std::chrono::duration<double>(t1 - t0).count();
  json record = {
      {"cell", cell_json(cell)}, {"version", where.version}, {"config_hash", config_hash(dir, cell)},
      {"host", where.host},      {"cpu", where.cpu},         {"cores", where.cores},
      {"job_id", where.job_id},  {"exit_code", exit_code},   {"wall_seconds", seconds}};
  if (exit_code != 0 || !fs::exists(partial / "summary.json", ec)) {
    record["error"] = last_line(log);
    fs::remove_all(partial, ec);
    util::write_file_bytes(failed_file(dir, cell), record.dump(1) + "\n");
    return CellState::Failed;
  }
  record["summary"] = read_json(partial / "summary.json");
  // Before the run and around it, up to here; the last write and rename take well under a millisecond.
  record["overhead_seconds"] = std::chrono::duration<double>(t0 - start + (Clock::now() - t1)).count();
  util::write_file_bytes(partial / "result.json", record.dump(1) + "\n");
  fs::remove(failed_file(dir, cell), ec);
  fs::remove_all(cell_folder(dir, cell), ec);  // an incomplete leftover of an earlier attempt
  fs::rename(partial, cell_folder(dir, cell), ec);
  if (ec)
    throw file_error(cell_folder(dir, cell), "cannot move the finished cell into place: " + ec.message());
  return CellState::Done;
}

std::vector<int> pending_cells(const fs::path& dir, const std::vector<SweepCell>& cells) {
  std::vector<int> pending;
  for (const SweepCell& c : cells)
    if (cell_state(dir, c) != CellState::Done) pending.push_back(c.index);
  return pending;
}

}  // namespace lrd::sweep
