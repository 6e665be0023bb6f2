#pragma once
// A full disk, portably and without root: in a child process whose files may not grow past a few
// bytes (RLIMIT_FSIZE, with SIGXFSZ ignored), every write past the limit fails with EFBIG, as one
// on a full disk fails with ENOSPC. The child runs the writer and reports its error.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <exception>
#include <filesystem>
#include <functional>
#include <set>
#include <string>

#include "lrd/util/error.h"

namespace lrd::test {

// The message of the lrd::Error `write` throws when no file may grow past `limit` bytes; "no
// error" when it throws none, and "not an lrd::Error: ..." for any other exception.
inline std::string error_with_file_size_limit(rlim_t limit, const std::function<void()>& write) {
  int fds[2];
  if (::pipe(fds) != 0) {
    ADD_FAILURE() << "pipe failed";
    return "";
  }
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(fds[0]);
    std::signal(SIGXFSZ, SIG_IGN);
    rlimit r{};
    ::getrlimit(RLIMIT_FSIZE, &r);
    r.rlim_cur = limit;
    ::setrlimit(RLIMIT_FSIZE, &r);
    std::string message = "no error";
    try {
      write();
    } catch (const lrd::Error& e) {
      message = e.what();
    } catch (const std::exception& e) {
      message = std::string("not an lrd::Error: ") + e.what();
    }
    // A pipe is no file: the limit does not apply to it.
    const char* p = message.data();
    std::size_t left = message.size();
    while (left > 0) {
      const ssize_t n = ::write(fds[1], p, left);
      if (n <= 0) break;
      p += n;
      left -= static_cast<std::size_t>(n);
    }
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string message;
  char buf[4096];
  for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;)
    message.append(buf, static_cast<std::size_t>(n));
  ::close(fds[0]);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the writer's process crashed";
  return message;
}

// The names in a folder (no temporary may be left beside a file).
inline std::set<std::string> names_in(const std::filesystem::path& dir) {
  std::set<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

}  // namespace lrd::test
