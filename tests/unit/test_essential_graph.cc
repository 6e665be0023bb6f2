// The measures the loop closer and global BA judge their solutions by: the change of each
// spanning-tree edge and tracking link (odometry_change.h), and the essential graph a loop
// correction optimizes (essential_graph.h), on keyframes made by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "keyframe_graph.h"
#include "lrd/loop/essential_graph.h"
#include "lrd/optim/odometry_change.h"

using lrd::map::KeyFrame;
using Graph = lrd::test::KeyFrameGraph;

namespace {
// n keyframes 10 cm apart, each the spanning-tree child of the one before.
void make_chain(Graph& g, int n, std::vector<KeyFrame*>& chain) {
  for (int k = 0; k < n; ++k) {
    chain.push_back(g.keyframe(Eigen::Isometry3d(Eigen::Translation3d(-0.1 * k, 0.0, 0.0))));
    if (k > 0) {
      g.points(20, {chain[k - 1], chain[k]});
      chain[k]->update_connections();
      ASSERT_EQ(chain[k]->parent(), chain[k - 1]);
    }
  }
}
}  // namespace

// The plausibility measure of loop corrections and global BA results (the divergence hunt,
// bench/results/divergence.md): each keyframe against its spanning-tree parent, after against
// before.
TEST(EssentialGraph, OdometryChangeNamesTheEdgeASolutionTearsMost) {
  Graph g;
  std::vector<KeyFrame*> chain;
  ASSERT_NO_FATAL_FAILURE(make_chain(g, 4, chain));
  const lrd::optim::PoseOf before = [](KeyFrame* k) { return k->T_cw(); };
  // The whole chain moved rigidly (a drift spread evenly): no edge changes.
  const Eigen::Isometry3d shift(Eigen::Translation3d(3.0, -2.0, 1.0) *
                                Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  const auto rigid =
      lrd::optim::largest_odometry_change(chain, before, [&](KeyFrame* k) { return k->T_cw() * shift; });
  EXPECT_LT(rigid.metres, 1e-9);
  EXPECT_LT(rigid.degrees, 1e-6);
  // Keyframe 2 and what follows it moved 0.4 m and 12 degrees: the edge 1-2 carries it all.
  const Eigen::Isometry3d tear(Eigen::AngleAxisd(12.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()) *
                               Eigen::Translation3d(0.0, 0.4, 0.0));
  const lrd::optim::PoseOf torn = [&](KeyFrame* k) {
    return k->id() >= chain[2]->id() ? tear * k->T_cw() : k->T_cw();
  };
  const auto change = lrd::optim::largest_odometry_change(chain, before, torn);
  EXPECT_EQ(change.keyframe, chain[2]->id());
  EXPECT_NEAR(change.degrees, 12.0, 1e-6);
  EXPECT_GT(change.metres, 0.35);
  // Edges the caller does not count are skipped.
  const auto skipped = lrd::optim::largest_odometry_change(chain, before, torn,
                                                           [&](const KeyFrame* k) { return k != chain[2]; });
  EXPECT_LT(skipped.metres, 1e-9);
}

// The loop correction's real solve is judged like its dry run: a solution that tears an edge
// beyond the limits gives way to the fallback (the dry run's poses), one within them stays.
TEST(EssentialGraph, ATornSolutionGivesWayToTheFallback) {
  Graph g;
  std::vector<KeyFrame*> chain;
  ASSERT_NO_FATAL_FAILURE(make_chain(g, 4, chain));
  const lrd::optim::PoseOf before = [](KeyFrame* k) { return k->T_cw(); };
  // Fallback: the chain moved 0.05 m a keyframe further from keyframe 0 (edges change 5 cm).
  // Torn: keyframes 2 and 3 moved 0.5 m at once (edge 1-2 changes 0.5 m).
  lrd::optim::SolvedPoses fallback, torn, spread;
  for (KeyFrame* k : chain) {
    const double i = static_cast<double>(k->id() - chain[0]->id());
    fallback[k->id()] = Eigen::Translation3d(0.05 * i, 0.0, 0.0) * k->T_cw();
    torn[k->id()] = Eigen::Translation3d(i >= 2 ? 0.5 : 0.0, 0.0, 0.0) * k->T_cw();
    spread[k->id()] = Eigen::Translation3d(0.1 * i, 0.0, 0.0) * k->T_cw();
  }
  const auto taken = lrd::optim::fall_back_if_torn(chain, before, torn, fallback, 0.25, 10.0);
  EXPECT_TRUE(taken.taken);
  EXPECT_NEAR(taken.change.metres, 0.5, 1e-9);
  EXPECT_EQ(taken.change.keyframe, chain[2]->id());
  EXPECT_EQ(taken.change.other, chain[1]->id());
  for (KeyFrame* k : chain) EXPECT_TRUE(torn.at(k->id()).isApprox(fallback.at(k->id()), 1e-12)) << k->id();
  // 10 cm an edge is within 0.25 m: the solution stays as it is.
  const lrd::optim::SolvedPoses spread_before = spread;
  const auto kept = lrd::optim::fall_back_if_torn(chain, before, spread, fallback, 0.25, 10.0);
  EXPECT_FALSE(kept.taken);
  EXPECT_NEAR(kept.change.metres, 0.1, 1e-9);
  for (KeyFrame* k : chain)
    EXPECT_EQ(spread.at(k->id()).matrix(), spread_before.at(k->id()).matrix()) << k->id();
}

// Corrections add up: each solution within the limits, several together can still take a pair far
// from its odometry as tracked. A tracking link keeps that odometry; a solution that takes the pair
// further than the limits from it is beyond them, one that brings it back or leaves it is not.
TEST(EssentialGraph, CorrectionsThatAddUpAreMeasuredFromTheTrackedOdometry) {
  Graph g;
  std::vector<KeyFrame*> chain;
  ASSERT_NO_FATAL_FAILURE(make_chain(g, 4, chain));
  chain[1]->add_tracking_link(chain[2]);  // tracked 0.1 m apart
  // Earlier corrections moved keyframes 2 and 3 0.2 m along y: the map as it is now.
  for (std::size_t i = 2; i < 4; ++i)
    chain[i]->set_pose(chain[i]->T_cw() * Eigen::Isometry3d(Eigen::Translation3d(0.0, -0.2, 0.0)));
  const lrd::optim::PoseOf before = [](KeyFrame* k) { return k->T_cw(); };
  const auto moved_y = [&](double dy) -> lrd::optim::PoseOf {
    return [&, dy](KeyFrame* k) {
      return k->id() >= chain[2]->id() ? k->T_cw() * Eigen::Isometry3d(Eigen::Translation3d(0.0, -dy, 0.0))
                                       : k->T_cw();
    };
  };
  // 0.1 m further: one step of 0.1 m, 0.3 m from the tracked odometry.
  const auto further = lrd::optim::largest_odometry_change(chain, before, moved_y(0.1));
  EXPECT_NEAR(further.metres, 0.1, 1e-9);
  EXPECT_NEAR(further.from_tracked_metres, 0.3, 1e-9);
  EXPECT_EQ(std::minmax(further.from_tracked_keyframe, further.from_tracked_other),
            std::minmax(chain[1]->id(), chain[2]->id()));
  EXPECT_FALSE(further.within(0.25, 10.0));
  EXPECT_NE(further.beyond(0.25, 10.0).find("as tracked"), std::string::npos);
  // 0.1 m back towards it: mending, within the limits although 0.1 m a step.
  const auto back = lrd::optim::largest_odometry_change(chain, before, moved_y(-0.1));
  EXPECT_NEAR(back.metres, 0.1, 1e-9);
  EXPECT_EQ(back.from_tracked_metres, 0.0);
  EXPECT_TRUE(back.within(0.25, 10.0));
  // Left where it is (0.2 m from the tracked odometry, within 0.25 m): within.
  const auto left = lrd::optim::largest_odometry_change(chain, before, before);
  EXPECT_TRUE(left.within(0.25, 10.0));
  EXPECT_TRUE(left.within(0.1, 10.0));  // not taken further: not held against it
  // A step beyond the limits is named as a step.
  const auto torn = lrd::optim::largest_odometry_change(chain, before, moved_y(0.4));
  EXPECT_EQ(torn.beyond(0.25, 10.0).find("move keyframe"), 0u);
}

// Consecutive frames can be tracked against keyframes far apart in the spanning tree: a solution
// that bends every edge between them a little moves them apart a lot, and the camera trajectory
// jumps between those frames. Their tracking link measures it.
TEST(EssentialGraph, OdometryChangeMeasuresTrackingLinksAcrossTheTree) {
  Graph g;
  std::vector<KeyFrame*> chain;
  ASSERT_NO_FATAL_FAILURE(make_chain(g, 6, chain));
  // Each keyframe k moved 0.1 * k m along y: every tree edge changes by 0.1 m.
  const lrd::optim::PoseOf before = [](KeyFrame* k) { return k->T_cw(); };
  const lrd::optim::PoseOf bent = [&](KeyFrame* k) {
    const auto k_index = static_cast<double>(std::find(chain.begin(), chain.end(), k) - chain.begin());
    return k->T_cw() * Eigen::Isometry3d(Eigen::Translation3d(0.0, -0.1 * k_index, 0.0));
  };
  const auto tree_only = lrd::optim::largest_odometry_change(chain, before, bent);
  EXPECT_NEAR(tree_only.metres, 0.1, 1e-9);
  // Frames tracked against keyframe 0 and then keyframe 5 link them: 0.5 m, named.
  chain[0]->add_tracking_link(chain[5]);
  const auto linked = lrd::optim::largest_odometry_change(chain, before, bent);
  EXPECT_NEAR(linked.metres, 0.5, 1e-9);
  EXPECT_EQ(std::minmax(linked.keyframe, linked.other), std::minmax(chain[0]->id(), chain[5]->id()));
  // The loop correction's pose graph holds the link too: five tree edges and the link.
  lrd::loop::EssentialGraph graph;
  graph.add_map_edges(chain, before, 100);
  EXPECT_EQ(graph.edges.size(), 6u);
}

// Frames tracked against a keyframe that culling removes follow its parent: so do its links.
TEST(EssentialGraph, ARemovedKeyframesTrackingLinksGoToItsParent) {
  Graph g;
  KeyFrame* kf0 = g.keyframe();
  KeyFrame* kf1 = g.keyframe(Eigen::Isometry3d(Eigen::Translation3d(-0.1, 0.0, 0.0)));
  KeyFrame* kf2 = g.keyframe(Eigen::Isometry3d(Eigen::Translation3d(-0.2, 0.0, 0.0)));
  KeyFrame* kf3 = g.keyframe(Eigen::Isometry3d(Eigen::Translation3d(-0.3, 0.0, 0.0)));
  g.points(30, {kf0, kf1});
  kf1->update_connections();
  g.points(30, {kf0, kf2});
  kf2->update_connections();
  g.points(30, {kf2, kf3});
  kf3->update_connections();
  ASSERT_EQ(kf1->parent(), kf0);
  ASSERT_EQ(kf3->parent(), kf2);
  kf1->add_tracking_link(kf3);
  kf1->add_tracking_link(kf0);
  {
    std::lock_guard lock(g.map.mutex());
    kf1->set_bad();
  }
  const auto ids = [](const KeyFrame* k) {
    std::set<std::uint64_t> s;
    for (const auto& [id, tracked] : k->tracking_links()) s.insert(id);
    return s;
  };
  EXPECT_TRUE(kf1->tracking_links().empty());
  EXPECT_EQ(ids(kf3), std::set<std::uint64_t>{kf0->id()});
  EXPECT_EQ(ids(kf0), std::set<std::uint64_t>{kf3->id()});  // not itself
  // The odometry as tracked goes with them, through the removed keyframe: kf0 to kf3 is 0.3 m.
  EXPECT_NEAR(kf0->tracking_links().at(kf3->id()).translation().x(), 0.3, 1e-9);
  EXPECT_TRUE(kf3->tracking_links().at(kf0->id()).isApprox(kf0->tracking_links().at(kf3->id()).inverse()));
}

TEST(EssentialGraph, HasOneEdgePerPairMeasuredWithTheGivenPoses) {
  Graph g;
  KeyFrame* kf0 = g.keyframe();
  KeyFrame* kf1 = g.keyframe(Eigen::Isometry3d(Eigen::Translation3d(-0.1, 0.0, 0.0)));
  KeyFrame* kf2 = g.keyframe(Eigen::Isometry3d(Eigen::Translation3d(-0.2, 0.0, 0.0)));
  g.points(30, {kf0, kf1});
  kf1->update_connections();
  g.points(30, {kf1, kf2});
  g.points(20, {kf0, kf2});  // covisibility besides the tree
  kf2->update_connections();
  ASSERT_EQ(kf2->parent(), kf1);
  lrd::loop::EssentialGraph graph;
  // A loop link measured first keeps its measurement: the map's own edge for the pair is skipped.
  const Eigen::Isometry3d loop_measured(Eigen::Translation3d(0.5, 0.0, 0.0));
  graph.add_edge(kf2, kf0, loop_measured);
  graph.add_edge(kf0, kf2, Eigen::Isometry3d::Identity());
  ASSERT_EQ(graph.edges.size(), 1u);
  const std::vector<KeyFrame*> all{kf0, kf1, kf2};
  graph.add_map_edges(
      all, [](KeyFrame* k) { return k->T_cw(); }, 15);
  ASSERT_EQ(graph.edges.size(), 3u);  // the loop link, the tree edges 1-0 and 2-1
  EXPECT_TRUE(graph.edges[0].T_to_from.isApprox(loop_measured));
  for (std::size_t i = 1; i < graph.edges.size(); ++i) {
    const auto& e = graph.edges[i];
    EXPECT_NEAR(e.T_to_from.translation().norm(), 0.1, 1e-9) << e.from << "->" << e.to;
  }
  // Without the loop link and above every weight: the tree alone.
  lrd::loop::EssentialGraph tree_only;
  tree_only.add_map_edges(
      all, [](KeyFrame* k) { return k->T_cw(); }, 1000);
  EXPECT_EQ(tree_only.edges.size(), 2u);
}
