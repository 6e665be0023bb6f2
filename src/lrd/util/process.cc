#include "lrd/util/process.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "lrd/util/error.h"

extern char** environ;

namespace lrd::util {

namespace fs = std::filesystem;

namespace {

// posix_spawn's file actions, released on every path out.
struct FileActions {
  posix_spawn_file_actions_t actions{};
  FileActions() { posix_spawn_file_actions_init(&actions); }
  ~FileActions() { posix_spawn_file_actions_destroy(&actions); }
  FileActions(const FileActions&) = delete;
  FileActions& operator=(const FileActions&) = delete;
};

int wait_for(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

}  // namespace

std::optional<fs::path> find_on_path(const std::string& program) {
  if (program.find('/') != std::string::npos) {
    if (access(program.c_str(), X_OK) == 0) return fs::path(program);
    return std::nullopt;
  }
  const char* path = std::getenv("PATH");
  std::string dirs = path != nullptr ? path : "/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    const fs::path candidate =
        fs::path(dirs.substr(start, end - start).empty() ? "." : dirs.substr(start, end - start)) / program;
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
    start = end + 1;
  }
  return std::nullopt;
}

fs::path own_executable() {
  std::error_code ec;
  fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw Error("cannot find this program's own path (/proc/self/exe): " + ec.message());
  return self;
}

ProcessResult run_process(const std::vector<std::string>& argv, const std::optional<fs::path>& log) {
  if (argv.empty()) throw Error("run_process: no program");
  const std::optional<fs::path> program = find_on_path(argv[0]);
  if (!program) throw Error(argv[0] + ": not found on PATH");
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  FileActions fa;
  int pipe_fds[2] = {-1, -1};
  if (log) {
    posix_spawn_file_actions_addopen(&fa.actions, STDOUT_FILENO, log->c_str(), O_WRONLY | O_CREAT | O_APPEND,
                                     0644);
    posix_spawn_file_actions_adddup2(&fa.actions, STDOUT_FILENO, STDERR_FILENO);
  } else {
    if (pipe(pipe_fds) != 0) throw Error(std::string("cannot create a pipe: ") + std::strerror(errno));
    posix_spawn_file_actions_adddup2(&fa.actions, pipe_fds[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&fa.actions, pipe_fds[0]);
    posix_spawn_file_actions_addclose(&fa.actions, pipe_fds[1]);
  }
  pid_t pid = 0;
  const int err = posix_spawn(&pid, program->c_str(), &fa.actions, nullptr, args.data(), environ);
  ProcessResult result;
  if (!log) {
    close(pipe_fds[1]);
    if (err == 0) {
      char buffer[4096];
      ssize_t n = 0;
      while ((n = read(pipe_fds[0], buffer, sizeof buffer)) != 0) {
        if (n < 0) {
          if (errno == EINTR) continue;
          break;
        }
        result.output.append(buffer, static_cast<std::size_t>(n));
      }
    }
    close(pipe_fds[0]);
  }
  if (err != 0) throw Error(argv[0] + ": cannot start: " + std::strerror(err));
  result.exit_code = wait_for(pid);
  return result;
}

}  // namespace lrd::util
