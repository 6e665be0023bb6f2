#include "lrd/eval/statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace lrd::eval {

double median(std::span<const double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::vector<double> sorted(values.begin(), values.end());
  std::sort(sorted.begin(), sorted.end());
  const std::size_t n = sorted.size();
  if (n % 2 == 1) return sorted[n / 2];
  return (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0;
}

ErrorStats compute_stats(std::span<const double> errors) {
  ErrorStats s;
  s.count = errors.size();
  if (errors.empty()) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    s.rmse = s.mean = s.median = s.std_dev = s.min = s.max = nan;
    return s;
  }
  const double n = static_cast<double>(errors.size());
  double sum = 0.0, sum_sq = 0.0;
  for (double e : errors) {
    sum += e;
    sum_sq += e * e;
  }
  s.rmse = std::sqrt(sum_sq / n);
  s.mean = sum / n;
  // Two-pass variance, as numpy.std computes it.
  double dev_sq = 0.0;
  for (double e : errors) dev_sq += (e - s.mean) * (e - s.mean);
  s.std_dev = std::sqrt(dev_sq / n);
  s.median = median(errors);
  const auto [lo, hi] = std::minmax_element(errors.begin(), errors.end());
  s.min = *lo;
  s.max = *hi;
  return s;
}

}  // namespace lrd::eval
