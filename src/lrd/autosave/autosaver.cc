#include "lrd/autosave/autosaver.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <optional>
#include <utility>

#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"

namespace lrd::autosave {

using Clock = std::chrono::steady_clock;

Autosaver::Autosaver(const System& system, AutosaveOptions options, Access access)
    : system_(system),
      options_(std::move(options)),
      access_(access ? std::move(access) : Access([](const std::function<void()>& save) { save(); })) {
  if (!(options_.period_seconds > 0.0))
    throw Error(fmt::format("autosave: the period must be a positive number of seconds, got {}",
                            options_.period_seconds));
  if (options_.map_file.empty() || options_.trajectory_file.empty())
    throw Error("autosave: needs a map file and a trajectory file to write");
}

Autosaver::~Autosaver() {
  stop();
}

void Autosaver::start() {
  if (capturer_.joinable()) return;
  writer_ = std::thread([this] { write(); });
  capturer_ = std::thread([this] { run(); });
}

void Autosaver::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  // The capturing thread finishes a save under way (it waits for the writer), then the writer.
  if (capturer_.joinable()) capturer_.join();
  {
    std::lock_guard lock(mutex_);
    writer_stopping_ = true;
  }
  job_changed_.notify_all();
  if (writer_.joinable()) writer_.join();
}

AutosaveStats Autosaver::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void Autosaver::on_frame(const events::FrameTracked& /*event*/) {
  {
    std::lock_guard lock(mutex_);
    ++frames_seen_;
  }
  wake_.notify_all();
}

void Autosaver::on_loop(const events::LoopClosed& /*event*/) {
  // The pose graph has just moved the keyframes: the map worth keeping is the corrected one.
  {
    std::lock_guard lock(mutex_);
    loop_pending_ = true;
  }
  wake_.notify_all();
}

void Autosaver::run() {
  const auto period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options_.period_seconds));
  // How long a due save waits for the next frame to be tracked; without frames (a paused camera,
  // the end of a sequence) it goes ahead.
  const auto frame_wait = std::min(period, Clock::duration(std::chrono::milliseconds(500)));
  auto next = Clock::now() + period;
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait_until(lock, next, [this] { return stopping_ || loop_pending_; });
    if (stopping_) return;
    const bool after_loop = std::exchange(loop_pending_, false);
    if (!after_loop && Clock::now() < next) continue;  // woken early, nothing asked
    // Just after a frame: the map mutex is then free of tracking until the next frame comes.
    const std::uint64_t seen = frames_seen_;
    wake_.wait_for(lock, frame_wait, [&] { return stopping_ || frames_seen_ != seen; });
    if (stopping_) return;
    lock.unlock();
    save(after_loop);
    next = Clock::now() + period;
    lock.lock();
  }
}

void Autosaver::save(bool after_loop) {
  saving_ = true;
  ++begun_;
  const auto t0 = Clock::now();
  double lock_seconds = 0.0;
  Job job;
  std::optional<std::string> error;  // why the save failed
  try {
    access_([&] {
      const PendingMapSave pending = system_.capture_map();
      const auto t1 = Clock::now();
      // The map first: a trajectory file never names frames of a map newer than the saved one.
      job.trajectory = system_.trajectory();
      lock_seconds = pending.lock_seconds() + std::chrono::duration<double>(Clock::now() - t1).count();
      job.pending = &pending;
      std::unique_lock lock(mutex_);
      job_ = &job;
      job_changed_.notify_all();
      // `pending` (and, for a node, the access that keeps the system from a reset) lives until
      // the writer has built the bytes.
      job_changed_.wait(lock, [&] { return job.serialized; });
    });
    std::unique_lock lock(mutex_);
    job_changed_.wait(lock, [&] { return job.written; });
    if (!job.error.empty()) error = job.error;
  } catch (const std::exception& e) {
    error = e.what();
  }
  // A full disk now may be free at the next save; the run goes on either way.
  if (error) spdlog::warn("autosave: {}", *error);
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  std::lock_guard lock(mutex_);
  saving_ = false;
  if (error) {
    ++stats_.failures;
    return;
  }
  ++stats_.saves;
  if (after_loop) ++stats_.loop_saves;
  stats_.save_seconds.push_back(seconds);
  stats_.lock_seconds.push_back(lock_seconds);
}

void Autosaver::write() {
  // The lowest priority, for this thread only (Linux: a thread's own nice value): on a busy
  // machine building and writing the bytes waits for tracking, never the other way round.
  (void)setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 19);
  std::unique_lock lock(mutex_);
  for (;;) {
    job_changed_.wait(lock, [this] { return job_ != nullptr || writer_stopping_; });
    if (job_ == nullptr) return;
    Job& job = *std::exchange(job_, nullptr);
    lock.unlock();
    std::string bytes, error;
    try {
      bytes = job.pending->serialize();
    } catch (const std::exception& e) {
      error = e.what();
    }
    lock.lock();
    job.serialized = true;
    job_changed_.notify_all();
    lock.unlock();
    if (error.empty()) {
      try {
        util::write_file_bytes(options_.map_file, bytes);
        io::write_trajectory_tum(options_.trajectory_file, job.trajectory);
      } catch (const std::exception& e) {
        error = e.what();
      }
    }
    lock.lock();
    job.error = std::move(error);
    job.written = true;
    job_changed_.notify_all();
  }
}

}  // namespace lrd::autosave
