#include "lrd/util/thread_priority.h"

#include <pthread.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace lrd::util {

void name_this_thread(const char* name) {
  pthread_setname_np(pthread_self(), name);
}

bool lower_this_thread_priority(int nice) {
  return setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), nice) == 0;
}

}  // namespace lrd::util
