// The ROS 2 node's colour/depth pairing: associate.py's nearest-within-max_dt rule, either stream
// first, each image used once, what can no longer pair dropped and counted.
#include <gtest/gtest.h>

#include "lrd/node/frame_pairer.h"

namespace lrd::node {
namespace {

TEST(FramePairer, PairsNearestWithinMaxDtWhicheverStreamComesFirst) {
  FramePairer<int> p(0.02, 10);
  EXPECT_FALSE(p.add_colour(1.000, 1));
  auto pair = p.add_depth(1.010, 101);
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->colour.image, 1);
  EXPECT_EQ(pair->depth.image, 101);
  EXPECT_DOUBLE_EQ(pair->colour.stamp, 1.000);
  EXPECT_FALSE(p.add_depth(1.040, 102));
  pair = p.add_colour(1.033, 2);
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->depth.image, 102);
  EXPECT_EQ(p.unpaired_dropped(), 0u);
}

TEST(FramePairer, TooFarApartNeverPairAndOlderImagesAreDroppedOncePassed) {
  FramePairer<int> p(0.02, 10);
  EXPECT_FALSE(p.add_colour(1.0, 1));
  EXPECT_FALSE(p.add_depth(1.05, 101));  // 50 ms: no pair
  EXPECT_FALSE(p.add_colour(2.0, 2));
  const auto pair = p.add_depth(2.001, 102);
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->colour.image, 2);
  // Colour 1 waited before the pair and depth 101 too: both can no longer pair.
  EXPECT_EQ(p.unpaired_dropped(), 2u);
}

TEST(FramePairer, AtMostCapacityWait) {
  FramePairer<int> p(0.02, 3);
  for (int i = 0; i < 5; ++i) EXPECT_FALSE(p.add_colour(i, i));
  EXPECT_EQ(p.unpaired_dropped(), 2u);
}

}  // namespace
}  // namespace lrd::node
