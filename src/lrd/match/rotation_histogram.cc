#include "lrd/match/rotation_histogram.h"

#include <cmath>

namespace lrd::match {

void RotationHistogram::add(float angle_a, float angle_b, std::size_t index) {
  float rot = angle_a - angle_b;
  if (rot < 0.0f) rot += 360.0f;
  int bin = static_cast<int>(std::lround(rot * (1.0f / 360.0f) * kBins));
  if (bin >= kBins || bin < 0) bin = 0;
  bins_[static_cast<std::size_t>(bin)].push_back(index);
}

std::vector<std::size_t> RotationHistogram::rejected() const {
  std::size_t m1 = 0, m2 = 0, m3 = 0;
  int i1 = -1, i2 = -1, i3 = -1;
  for (int i = 0; i < kBins; ++i) {
    const std::size_t s = bins_[static_cast<std::size_t>(i)].size();
    if (s > m1) {
      m3 = m2, i3 = i2;
      m2 = m1, i2 = i1;
      m1 = s, i1 = i;
    } else if (s > m2) {
      m3 = m2, i3 = i2;
      m2 = s, i2 = i;
    } else if (s > m3) {
      m3 = s, i3 = i;
    }
  }
  if (static_cast<double>(m2) < 0.1 * static_cast<double>(m1))
    i2 = i3 = -1;
  else if (static_cast<double>(m3) < 0.1 * static_cast<double>(m1))
    i3 = -1;
  std::vector<std::size_t> out;
  for (int i = 0; i < kBins; ++i) {
    if (i == i1 || i == i2 || i == i3) continue;
    out.insert(out.end(), bins_[static_cast<std::size_t>(i)].begin(),
               bins_[static_cast<std::size_t>(i)].end());
  }
  return out;
}

}  // namespace lrd::match
