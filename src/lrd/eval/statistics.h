#pragma once
// Summary statistics of per-pair errors, defined as the numpy calls in TUM's scripts:
// rmse = sqrt(dot(e, e) / n), numpy.mean, numpy.median (mean of the two middle values for even n),
// numpy.std (population, ddof 0), numpy.min, numpy.max.
#include <cstddef>
#include <span>

namespace lrd::eval {

struct ErrorStats {
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double std_dev = 0.0;  // population (ddof 0)
  double min = 0.0;
  double max = 0.0;
  std::size_t count = 0;
};

// All statistics are NaN (count 0) for an empty input.
[[nodiscard]] ErrorStats compute_stats(std::span<const double> errors);

// numpy.median; NaN for an empty input (as numpy returns, with a warning).
[[nodiscard]] double median(std::span<const double> values);

}  // namespace lrd::eval
