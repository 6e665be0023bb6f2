#pragma once
// Child processes for the sweep: a program run with its output in a log file, and programs found
// on PATH (the sweep calls `lrdslam run` and Slurm's sbatch/squeue/scancel, linking neither).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace lrd::util {

struct ProcessResult {
  int exit_code = -1;  // the program's, or 128 + the signal that ended it
  std::string output;  // stdout (stderr too unless a log file took it) when captured
};

// Runs `argv` (argv[0] a path, or a name looked up on PATH) and waits for it. With `log`,
// stdout and stderr go to that file (appended); else stdout is captured and stderr inherited.
// Throws lrd::Error when the program cannot be started.
[[nodiscard]] ProcessResult run_process(const std::vector<std::string>& argv,
                                        const std::optional<std::filesystem::path>& log = std::nullopt);

// The program's path on PATH, if it is there.
[[nodiscard]] std::optional<std::filesystem::path> find_on_path(const std::string& program);

// This process's own executable (/proc/self/exe).
[[nodiscard]] std::filesystem::path own_executable();

}  // namespace lrd::util
