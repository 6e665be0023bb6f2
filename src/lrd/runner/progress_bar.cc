#include "lrd/runner/progress_bar.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>

namespace lrd::runner {

ProgressBar::ProgressBar(std::size_t total, bool enabled)
    : total_(total),
      enabled_(enabled),
      tty_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()) {
  last_draw_ = start_;
}

void ProgressBar::update(std::size_t done, const std::string& status) {
  if (!enabled_ || total_ == 0) return;
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double fps = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
  if (tty_) {
    if (done != total_ && drawn_ && now - last_draw_ < std::chrono::milliseconds(100)) return;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(kWidth * done / total_);
    std::string bar(static_cast<std::size_t>(filled), '=');
    if (filled < kWidth) bar += '>' + std::string(static_cast<std::size_t>(kWidth - filled - 1), ' ');
    std::fputs(
        fmt::format("\r[{}] {}/{} frames {:5.1f} fps  {}\x1b[K", bar, done, total_, fps, status).c_str(),
        stderr);
    std::fflush(stderr);
    last_draw_ = now;
    drawn_ = true;
  } else {
    const std::size_t decile = 10 * done / total_;
    if (decile <= last_decile_ && done != total_) return;
    if (decile == last_decile_ && drawn_) return;
    last_decile_ = decile;
    drawn_ = true;
    std::fputs(
        fmt::format("{:3}% {}/{} frames {:5.1f} fps  {}\n", 100 * done / total_, done, total_, fps, status)
            .c_str(),
        stderr);
  }
}

void ProgressBar::finish() {
  if (enabled_ && tty_ && drawn_) std::fputs("\n", stderr);
}

}  // namespace lrd::runner
