#pragma once
// A one-line progress display on stderr: frames done, frames per second and tracking state.
// Redrawn in place on a terminal (at most 10 times a second); one line per 10 % otherwise, so
// logs of CI runs stay short.
#include <chrono>
#include <cstddef>
#include <string>

namespace lrd::runner {

class ProgressBar {
 public:
  ProgressBar(std::size_t total, bool enabled);
  void update(std::size_t done, const std::string& status);
  void finish();

 private:
  std::size_t total_;
  bool enabled_;
  bool tty_;
  std::size_t last_decile_ = 0;
  std::chrono::steady_clock::time_point start_, last_draw_;
  bool drawn_ = false;
};

}  // namespace lrd::runner
