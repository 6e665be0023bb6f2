#pragma once
// Improvement rate of the LRD-SLAM paper (Eq. 12): eta = (o - r) / o * 100 %, o the baseline's
// figure and r ours. Positive means ours is lower (better).
#include "lrd/eval/statistics.h"

namespace lrd::eval {

// NaN when the baseline figure is 0 (no improvement rate is defined).
[[nodiscard]] double improvement_percent(double baseline, double ours);

// Per statistic; `count` is left 0 as a rate of pair counts means nothing.
[[nodiscard]] ErrorStats improvement_percent(const ErrorStats& baseline, const ErrorStats& ours);

}  // namespace lrd::eval
