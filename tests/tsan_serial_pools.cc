// Linked into lrdslam_tests in the tsan preset only. libtbb and OpenCV are not built with
// ThreadSanitizer, so the hand-offs inside their thread pools (a TBB task's data, an OpenCV
// matrix's reference count) are invisible to it and every parallel_for reads as a race. With both
// pools serial, the work they split runs on the thread that asked for it, and every thread of
// ours (tracking, local mapping, loop closing, global BA, segmentation, dense, prefetch, publisher)
// is still there for ThreadSanitizer to watch.
#include <tbb/global_control.h>

#include <opencv2/core.hpp>

namespace {

struct SerialPools {
  SerialPools() { cv::setNumThreads(0); }
  tbb::global_control serial_tbb{tbb::global_control::max_allowed_parallelism, 1};
};

const SerialPools serial_pools;

}  // namespace
