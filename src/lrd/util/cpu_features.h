#pragma once
// A hot loop in two copies, chosen at run time (bench/results/performance.md): the same C++ inlined
// into a baseline function and into one compiled with [[gnu::target("avx2")]], where the compiler
// can make it. Without -mavx2 for the whole build, the binary still runs on any x86-64, and the
// libraries we link (Eigen in Ceres, OpenCV) keep the layouts they were built with.
#if defined(__GNUC__) && defined(__x86_64__)
#define LRD_AVX2_COPIES 1
#endif

#include <atomic>

namespace lrd::util {

namespace detail {
inline std::atomic<bool> baseline_copies_only{false};
}  // namespace detail

// Tests: run the baseline copies even where the CPU has AVX2, so that both copies are checked on
// any machine (they must give the same bits).
inline void use_baseline_copies_only(bool only) {
  detail::baseline_copies_only.store(only);
}

// Whether this CPU runs AVX2 and the build made AVX2 copies (LRD_AVX2_COPIES), unless a test
// asked for the baseline ones.
[[nodiscard]] inline bool cpu_has_avx2() {
#ifdef LRD_AVX2_COPIES
  static const bool has = __builtin_cpu_supports("avx2");
  return has && !detail::baseline_copies_only.load(std::memory_order_relaxed);
#else
  return false;
#endif
}

}  // namespace lrd::util
