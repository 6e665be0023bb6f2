#pragma once
// Test hook: make one worker thread fail on purpose, to check that its error ends the run with a
// one-line error naming the thread (never std::terminate, never a hang). The point is chosen by
// the environment variable LRDSLAM_FAIL_AT (read once) or by set_fault_point() in tests:
//   local_mapping, loop_closing, global_ba, segmentation, dense, prefetcher
// Unset (always in normal use), check_fault_point() costs a call_once check and one atomic load.
#include <string>

namespace lrd::util {

// Throws lrd::Error("injected failure at <point> (LRDSLAM_FAIL_AT)") when `point` is the chosen one.
void check_fault_point(const char* point);
// Chooses the point from now on ("" clears it); overrides the environment.
void set_fault_point(const std::string& point);

}  // namespace lrd::util
