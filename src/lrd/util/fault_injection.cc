#include "lrd/util/fault_injection.h"

#include <atomic>
#include <cstdlib>
#include <mutex>

#include "lrd/util/error.h"

namespace lrd::util {

namespace {
std::mutex mutex;
std::string chosen;
std::atomic<bool> armed{false};
std::once_flag from_environment;

void read_environment() {
  std::call_once(from_environment, [] {
    const char* value = std::getenv("LRDSLAM_FAIL_AT");
    if (value == nullptr || *value == '\0') return;
    std::lock_guard lock(mutex);
    chosen = value;
    armed.store(true);
  });
}
}  // namespace

void check_fault_point(const char* point) {
  read_environment();
  if (!armed.load(std::memory_order_relaxed)) return;
  std::lock_guard lock(mutex);
  if (chosen == point) throw Error(std::string("injected failure at ") + point + " (LRDSLAM_FAIL_AT)");
}

void set_fault_point(const std::string& point) {
  read_environment();
  std::lock_guard lock(mutex);
  chosen = point;
  armed.store(!point.empty());
}

}  // namespace lrd::util
