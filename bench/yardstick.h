#pragma once
// The yardstick Y (lrd/util/yardstick.h), by the names the benchmarks use, and Y as a run measures
// it beside the work it divides.
#include <cstdio>
#include <stdexcept>

#include "lrd/runner/sequence_runner.h"
#include "lrd/util/yardstick.h"

namespace lrd::bench {

using util::median_of;
using util::yardstick_ms;

// Y of one run made with RunOptions::yardstick (bench/results/performance.md): the median of
// OpenCV's ORB timed on each frame's grey image in the tracking thread, right after our own
// extraction, under the same competition from the other threads. The first call in a benchmark
// prints it beside `apart_ms`, Y measured apart (sequence_yardstick_ms: up to 100 frames in a tight
// loop before the runs), so that the change of basis is on record.
inline double run_yardstick_ms(const runner::RunReport& report, double apart_ms) {
  const double y = report.yardstick.median_ms;
  if (!(y > 0.0)) throw std::runtime_error("the run measured no yardstick (RunOptions::yardstick is off)");
  static bool printed = false;
  if (!printed) {
    std::printf(
        "Y: %.2f ms interleaved (OpenCV ORB in the tracking thread beside each frame's extraction; the "
        "basis of every ratio below); %.2f ms measured apart before the runs (the old basis): "
        "interleaved / apart = %.2f\n",
        y, apart_ms, y / apart_ms);
    printed = true;
  }
  return y;
}

}  // namespace lrd::bench
