#include "lrd/eval/improvement.h"

#include <limits>

namespace lrd::eval {

double improvement_percent(double baseline, double ours) {
  if (baseline == 0.0) return std::numeric_limits<double>::quiet_NaN();
  return (baseline - ours) / baseline * 100.0;
}

ErrorStats improvement_percent(const ErrorStats& baseline, const ErrorStats& ours) {
  ErrorStats eta;
  eta.rmse = improvement_percent(baseline.rmse, ours.rmse);
  eta.mean = improvement_percent(baseline.mean, ours.mean);
  eta.median = improvement_percent(baseline.median, ours.median);
  eta.std_dev = improvement_percent(baseline.std_dev, ours.std_dev);
  eta.min = improvement_percent(baseline.min, ours.min);
  eta.max = improvement_percent(baseline.max, ours.max);
  eta.count = 0;
  return eta;
}

}  // namespace lrd::eval
