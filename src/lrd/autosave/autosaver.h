#pragma once
// A map that survives the process: while frames are tracked, the map and the trajectory so far
// are written every few seconds and after each loop closure, each file whole or not at all
// (util/atomic_file.h). A process killed at any moment (a watchdog's SIGKILL, a power cut after
// the sync) leaves the last complete save: a map file that loads (System::load_map, to go on in
// the same map frame) and a trajectory that parses.
//
// Without stalling tracking: a save begins just after a frame was tracked (a live camera leaves
// tracking idle until the next one) and holds the map mutex only while the map's changing parts
// are copied (System::capture_map), on a thread of normal priority so that it is never preempted
// holding it; the bytes are built and written by a second thread at the lowest CPU priority, so
// that on a busy machine the save, not tracking, waits.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "lrd/events/events.h"
#include "lrd/io/trajectory.h"
#include "lrd/system.h"

namespace lrd::autosave {

struct AutosaveOptions {
  double period_seconds = 0.0;            // > 0
  std::filesystem::path map_file;         // the map (.lrdmap)
  std::filesystem::path trajectory_file;  // the trajectory so far (TUM format)
};

// What the saves cost, for the summary and the benchmark.
struct AutosaveStats {
  std::size_t saves = 0;
  std::size_t loop_saves = 0;        // of those, started by a loop closure
  std::size_t failures = 0;          // saves that could not be written (logged; the next one tries again)
  std::vector<double> save_seconds;  // per save: capture, bytes, both files written and synced
  std::vector<double> lock_seconds;  // per save: the map mutex held for the map and the trajectory
};

class Autosaver final : public events::Subscriber {
 public:
  // Each save's copy of the map and the building of its bytes run inside `access`, which the
  // caller may use to keep the system from being reset or destroyed meanwhile (a node's reset);
  // by default it just calls.
  using Access = std::function<void(const std::function<void()>&)>;
  // Throws lrd::Error when the period is not positive or a file is not named. Subscribe it to the
  // system (System::subscribe, before the first frame) for the saves at loop closures, then start().
  Autosaver(const System& system, AutosaveOptions options, Access access = {});
  ~Autosaver() override;
  Autosaver(const Autosaver&) = delete;
  Autosaver& operator=(const Autosaver&) = delete;

  void start();
  // Finishes a save under way and joins both threads; no further save. Idempotent.
  void stop();

  // A save is being made now, or the count of saves begun: a frame tracked while either changed
  // overlapped a save (the benchmark's tracking time during saves).
  [[nodiscard]] bool saving() const { return saving_.load(); }
  [[nodiscard]] std::size_t saves_begun() const { return begun_.load(); }
  [[nodiscard]] AutosaveStats stats() const;

  void on_frame(const events::FrameTracked& event) override;
  void on_loop(const events::LoopClosed& event) override;

 private:
  void run();  // the capturing thread
  void save(bool after_loop);
  void write();  // the writing thread
  // The writing thread's part of one save: build the bytes while `pending` lives, then write.
  struct Job {
    const PendingMapSave* pending = nullptr;
    io::Trajectory trajectory;
    bool serialized = false, written = false;
    std::string error;  // empty: both files written
  };

  const System& system_;
  const AutosaveOptions options_;
  const Access access_;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  bool writer_stopping_ = false;  // set once the capturing thread has ended
  bool loop_pending_ = false;
  std::uint64_t frames_seen_ = 0;  // FrameTracked events so far
  AutosaveStats stats_;
  Job* job_ = nullptr;  // handed to the writing thread (mutex_)
  std::condition_variable job_changed_;
  std::atomic<bool> saving_{false};
  std::atomic<std::size_t> begun_{0};
  std::thread writer_, capturer_;
};

}  // namespace lrd::autosave
