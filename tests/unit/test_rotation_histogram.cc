// The rotation-consistency histogram: matches outside the three most populated bins of the
// orientation change are rejected, and bins under 10 % of the largest never count.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "lrd/match/rotation_histogram.h"

using lrd::match::RotationHistogram;

namespace {

std::set<std::size_t> rejected_set(const RotationHistogram& h) {
  const auto r = h.rejected();
  return {r.begin(), r.end()};
}

}  // namespace

TEST(RotationHistogram, EmptyRejectsNothing) {
  EXPECT_TRUE(RotationHistogram().rejected().empty());
}

TEST(RotationHistogram, ScatteredMatchesAroundADominantRotationAreRejected) {
  // 60 matches rotated by ~20 degrees (a little jitter, all inside one 12-degree bin), 6 matches at
  // unrelated angles, each alone in its bin: 1 < 10 % of 60, so none of their bins counts.
  RotationHistogram h;
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> base(0.0f, 360.0f), jitter(-3.0f, 3.0f);
  std::size_t idx = 0;
  std::set<std::size_t> scattered;
  for (int k = 0; k < 60; ++k) {
    const float b = base(rng);
    h.add(std::fmod(b + 24.0f + jitter(rng), 360.0f), b, idx++);
  }
  for (const float rot : {75.0f, 130.0f, 170.0f, 222.0f, 268.0f, 310.0f}) {
    const float b = base(rng);
    h.add(std::fmod(b + rot, 360.0f), b, idx);
    scattered.insert(idx++);
  }
  EXPECT_EQ(rejected_set(h), scattered);
}

TEST(RotationHistogram, KeepsTheThreeLargestBinsAboveTenPercent) {
  // Bins of 40, 20, 10 and 8 matches: the three largest stay, the fourth goes although it holds
  // more than 10 % of the largest.
  RotationHistogram h;
  std::size_t idx = 0;
  std::set<std::size_t> fourth;
  auto fill = [&](float rot, int n, std::set<std::size_t>* record) {
    for (int k = 0; k < n; ++k) {
      const float b = static_cast<float>(k * 7 % 360);
      h.add(std::fmod(b + rot + 360.0f, 360.0f), b, idx);
      if (record) record->insert(idx);
      ++idx;
    }
  };
  fill(0.0f, 40, nullptr);
  fill(36.0f, 20, nullptr);
  fill(-60.0f, 10, nullptr);
  fill(180.0f, 8, &fourth);
  EXPECT_EQ(rejected_set(h), fourth);
}

TEST(RotationHistogram, SecondAndThirdBinsBelowTenPercentOfTheFirstDoNotCount) {
  RotationHistogram a;  // 50, 6, 4: the third bin (4 < 5) goes, the second (6 >= 5) stays
  std::size_t idx = 0;
  for (int k = 0; k < 50; ++k) a.add(100.0f, 100.0f, idx++);
  for (int k = 0; k < 6; ++k) a.add(160.0f, 100.0f, idx++);
  std::set<std::size_t> third;
  for (int k = 0; k < 4; ++k) {
    third.insert(idx);
    a.add(220.0f, 100.0f, idx++);
  }
  EXPECT_EQ(rejected_set(a), third);

  RotationHistogram b;  // 50, 4, 4: both small bins go
  idx = 0;
  for (int k = 0; k < 50; ++k) b.add(100.0f, 100.0f, idx++);
  std::set<std::size_t> small;
  for (int k = 0; k < 8; ++k) {
    small.insert(idx);
    b.add(k < 4 ? 160.0f : 220.0f, 100.0f, idx++);
  }
  EXPECT_EQ(rejected_set(b), small);
}

TEST(RotationHistogram, SmallRotationsEitherSideOfZeroShareABin) {
  // -2 degrees wraps to 358, which must fall in the same bin as +2 (and 0).
  RotationHistogram h;
  std::size_t idx = 0;
  for (int k = 0; k < 10; ++k) h.add(10.0f, 12.0f, idx++);  // -2
  for (int k = 0; k < 10; ++k) h.add(12.0f, 10.0f, idx++);  // +2
  for (int k = 0; k < 10; ++k) h.add(359.0f, 1.0f, idx++);  // +358 = -2
  for (int k = 0; k < 10; ++k) h.add(50.0f, 50.0f, idx++);  // 0
  // Three more populated bins, each bigger than 10 % of the largest: if the zero-rotation
  // matches were split over two bins, one of these would displace part of them.
  for (int k = 0; k < 9; ++k) h.add(100.0f, 0.0f, idx++);
  for (int k = 0; k < 8; ++k) h.add(200.0f, 0.0f, idx++);
  for (int k = 0; k < 7; ++k) h.add(300.0f, 0.0f, idx++);
  const auto r = rejected_set(h);
  for (std::size_t i = 0; i < 40; ++i) EXPECT_EQ(r.count(i), 0u) << i;
  // Bins of 9 and 8 are the second and third; the 7 go.
  EXPECT_EQ(r.size(), 7u);
  EXPECT_EQ(*r.begin(), 57u);
}
