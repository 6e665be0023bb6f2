#pragma once
// Background threads below tracking's priority: on a busy machine the dense map and the event
// subscribers wait, the camera does not (Linux per-thread nice value). And their names, so that a
// profile (`perf report --sort comm`), top -H or gdb tells the stages apart.
namespace lrd::util {

// Names the calling thread ("lrd-mapping", ...; Linux keeps the first 15 characters).
void name_this_thread(const char* name);

// Sets the calling thread's nice value (19: the lowest priority). False where the system refuses;
// harmless then, the thread runs at the normal priority.
bool lower_this_thread_priority(int nice = 19);

}  // namespace lrd::util
