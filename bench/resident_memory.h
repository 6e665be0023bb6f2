#pragma once
// Resident memory of this process for the long-run benchmarks (bench_memory, bench_scale).
#include <unistd.h>

#include <fstream>

namespace lrd::bench {

// Resident set size of this process (Linux /proc/self/statm), in MiB.
inline double resident_mib() {
  std::ifstream statm("/proc/self/statm");
  long pages_total = 0, pages_resident = 0;
  statm >> pages_total >> pages_resident;
  return static_cast<double>(pages_resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

}  // namespace lrd::bench
