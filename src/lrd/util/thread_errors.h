#pragma once
// The first error of any worker thread, kept for the thread that owns the workers: a worker
// catches what it throws, records it here with its thread's name and stops; the owner rethrows it
// as one lrd::Error ("local mapping thread: ...") at its next call, so no exception leaves a
// thread function.
#include <atomic>
#include <exception>
#include <mutex>
#include <string>

#include "lrd/util/error.h"
#include "lrd/util/exception_message.h"

namespace lrd::util {

class ThreadErrors {
 public:
  // Call inside a catch block (it reads std::current_exception()). Later errors are dropped: the
  // first is the cause.
  void capture(const std::string& thread) noexcept {
    try {
      const std::string message = exception_message(std::current_exception());
      std::lock_guard lock(mutex_);
      if (has_error_.load()) return;
      try {
        message_ = thread + " thread: " + message;
      } catch (...) {
        message_ = "out of memory";  // no room for the thread's name; this fits the string's own buffer
      }
      has_error_.store(true);
    } catch (...) {  // not even the lock: keep that there was an error (rethrow() says which)
      has_error_.store(true);
    }
  }
  // Forgets the error (System::reset starts a new map).
  void clear() {
    std::lock_guard lock(mutex_);
    message_.clear();
    has_error_.store(false);
  }
  [[nodiscard]] bool has_error() const { return has_error_.load(); }
  [[nodiscard]] std::string message() const {
    std::lock_guard lock(mutex_);
    return message_;
  }
  // Throws the first error, if there is one.
  void rethrow() const {
    if (!has_error_.load()) return;
    std::string text = message();
    throw Error(text.empty() ? "out of memory" : text);  // empty: capture() found no memory for it
  }

 private:
  mutable std::mutex mutex_;
  std::string message_;
  std::atomic<bool> has_error_{false};
};

}  // namespace lrd::util
