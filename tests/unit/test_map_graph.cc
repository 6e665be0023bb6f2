// The map's bookkeeping: covisibility weights and the 15-point threshold, the spanning tree, the
// removal of a keyframe (children re-attached, pose kept relative to the parent), and the map
// points' observation counting, medoid descriptor and duplicate replacement. Keyframes are
// copies of one real frame (features of a rendered textured plane) with hand-made observations.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "keyframe_graph.h"
#include "lrd/map/map.h"

using lrd::data::Frame;
using lrd::map::KeyFrame;
using lrd::map::Map;
using lrd::map::MapPoint;

namespace {

using Graph = lrd::test::KeyFrameGraph;

std::vector<KeyFrame*> as_vector(const std::set<KeyFrame*, lrd::map::ById>& s) {
  return {s.begin(), s.end()};
}

// The pose of a keyframe, through the chain of removed keyframes to a live one (as the
// trajectory output does for frames whose reference keyframe was culled).
Eigen::Isometry3d resolve(KeyFrame* kf) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  while (kf->is_bad() && kf->parent() != nullptr) {
    T = T * kf->T_c_parent();
    kf = kf->parent();
  }
  return T * kf->T_cw();
}

}  // namespace

TEST(KeyFrameGraph, CovisibilityWeightsThresholdAndSpanningTree) {
  Graph g;
  ASSERT_GT(g.stereo.size(), 200u);
  KeyFrame* kf0 = g.keyframe();
  KeyFrame* kf1 = g.keyframe();
  g.points(40, {kf0, kf1});
  kf1->update_connections();
  EXPECT_EQ(kf1->weight(kf0), 40);
  EXPECT_EQ(kf0->weight(kf1), 40);
  EXPECT_EQ(kf1->parent(), kf0);
  EXPECT_EQ(as_vector(kf0->children()), std::vector<KeyFrame*>{kf1});
  EXPECT_EQ(kf0->parent(), nullptr);

  // kf2: 20 points with kf1, 10 with kf0 (under the threshold of 15).
  KeyFrame* kf2 = g.keyframe();
  g.points(20, {kf1, kf2});
  g.points(10, {kf0, kf2});
  kf2->update_connections();
  EXPECT_EQ(kf2->weight(kf1), 20);
  EXPECT_EQ(kf1->weight(kf2), 20);
  EXPECT_EQ(kf2->weight(kf0), 10);  // its own count is kept ...
  EXPECT_EQ(kf0->weight(kf2), 0);   // ... but the weak edge is not added on the other side
  EXPECT_EQ(kf2->ordered_covisibles(), std::vector<KeyFrame*>{kf1});
  EXPECT_EQ(kf2->covisibles_with_weight(15), std::vector<KeyFrame*>{kf1});
  EXPECT_EQ(kf2->parent(), kf1);
  EXPECT_EQ(kf1->ordered_covisibles(), (std::vector<KeyFrame*>{kf0, kf2}));
  EXPECT_EQ(kf1->best_covisibles(1), std::vector<KeyFrame*>{kf0});
  EXPECT_EQ(kf1->covisibles_with_weight(21), std::vector<KeyFrame*>{kf0});

  // kf3: nothing reaches 15 (5 with kf2, 3 with kf0): only the strongest edge is made.
  KeyFrame* kf3 = g.keyframe();
  g.points(5, {kf2, kf3});
  g.points(3, {kf0, kf3});
  kf3->update_connections();
  EXPECT_EQ(kf3->ordered_covisibles(), std::vector<KeyFrame*>{kf2});
  EXPECT_EQ(kf2->weight(kf3), 5);
  EXPECT_EQ(kf0->weight(kf3), 0);
  EXPECT_EQ(kf3->weight(kf0), 3);
  EXPECT_EQ(kf3->parent(), kf2);

  // kf4: equal weights with kf1 and kf2, the tie goes to the lower id (parent included).
  KeyFrame* kf4 = g.keyframe();
  g.points(18, {kf2, kf4});
  g.points(18, {kf1, kf4});
  kf4->update_connections();
  EXPECT_EQ(kf4->ordered_covisibles(), (std::vector<KeyFrame*>{kf1, kf2}));
  EXPECT_EQ(kf4->parent(), kf1);
  EXPECT_EQ(as_vector(kf1->children()), (std::vector<KeyFrame*>{kf2, kf4}));

  // A point seen by three keyframes counts once for each pair; bad points do not count.
  MapPoint* shared = g.point({kf0, kf1, kf2});
  kf1->update_connections();
  EXPECT_EQ(kf1->weight(kf0), 41);
  EXPECT_EQ(kf0->weight(kf1), 41);
  EXPECT_EQ(kf1->weight(kf2), 21);
  EXPECT_EQ(kf1->ordered_covisibles(), (std::vector<KeyFrame*>{kf0, kf2, kf4}));
  EXPECT_EQ(kf1->parent(), kf0);  // the tree is set once
  shared->set_bad();
  kf1->update_connections();
  EXPECT_EQ(kf1->weight(kf0), 40);
  EXPECT_EQ(kf1->weight(kf2), 20);

  // Keyframe 0 updating its own edges: its strong neighbour only.
  kf0->update_connections();
  EXPECT_EQ(kf0->ordered_covisibles(), std::vector<KeyFrame*>{kf1});
  EXPECT_EQ(kf0->parent(), nullptr);
  // Essential graph: parent, children and strong covisibility edges.
  EXPECT_EQ(kf1->essential_neighbours(), (std::vector<KeyFrame*>{kf0, kf2, kf4}));
  EXPECT_EQ(kf3->essential_neighbours(), std::vector<KeyFrame*>{kf2});
}

TEST(KeyFrameGraph, RemovalReattachesChildrenAndKeepsThePoseRelativeToTheParent) {
  Graph g;
  KeyFrame* kf0 = g.keyframe(lrd::test::pose(0.0, 0.0, 0.0, 0.0, 0.0, 0.0));
  KeyFrame* kf1 = g.keyframe(lrd::test::pose(0.01, 0.02, 0.0, 0.1, 0.0, 0.0));
  KeyFrame* kf2 = g.keyframe(lrd::test::pose(0.02, 0.05, -0.01, 0.2, 0.01, 0.0));
  KeyFrame* kf3 = g.keyframe(lrd::test::pose(0.03, 0.08, 0.02, 0.3, -0.02, 0.05));
  KeyFrame* kf4 = g.keyframe(lrd::test::pose(-0.03, 0.1, 0.0, 0.2, 0.1, 0.1));
  const auto pairs01 = g.points(30, {kf0, kf1});
  kf1->update_connections();
  g.points(40, {kf1, kf2});
  g.points(20, {kf0, kf2});
  kf2->update_connections();
  const auto triples = g.points(25, {kf1, kf2, kf3});
  g.points(30, {kf1, kf3});
  kf3->update_connections();
  g.points(35, {kf1, kf4});  // kf4 knows only kf1
  kf4->update_connections();
  ASSERT_EQ(kf1->parent(), kf0);
  ASSERT_EQ(kf2->parent(), kf1);
  ASSERT_EQ(kf3->parent(), kf1);
  ASSERT_EQ(kf4->parent(), kf1);
  ASSERT_EQ(kf3->weight(kf2), 25);

  const Eigen::Isometry3d T1 = kf1->T_cw(), T2 = kf2->T_cw(), T3 = kf3->T_cw();
  std::vector<std::size_t> pairs01_idx;
  for (MapPoint* mp : pairs01) pairs01_idx.push_back(*mp->index_in(kf0));
  const std::size_t points_before = g.map.map_point_count();
  kf1->set_bad();
  EXPECT_TRUE(kf1->is_bad());
  EXPECT_EQ(g.map.keyframes(), (std::vector<KeyFrame*>{kf0, kf2, kf3, kf4}));
  EXPECT_EQ(g.map.keyframe(1), nullptr);
  EXPECT_EQ(g.map.keyframe(2), kf2);
  // Children: kf2 goes under kf0 (its strongest edge to an attached keyframe), then kf3 under kf2
  // (kf3 sees kf2 only); kf4 has no edge to any attached keyframe and falls back to kf1's parent.
  EXPECT_EQ(kf2->parent(), kf0);
  EXPECT_EQ(kf3->parent(), kf2);
  EXPECT_EQ(kf4->parent(), kf0);
  EXPECT_EQ(as_vector(kf0->children()), (std::vector<KeyFrame*>{kf2, kf4}));
  EXPECT_EQ(as_vector(kf2->children()), std::vector<KeyFrame*>{kf3});
  EXPECT_TRUE(kf1->children().empty());
  EXPECT_EQ(kf1->parent(), kf0);
  // Covisibility edges to it are gone.
  for (KeyFrame* kf : {kf0, kf2, kf3, kf4}) {
    EXPECT_EQ(kf->weight(kf1), 0);
    for (KeyFrame* n : kf->ordered_covisibles()) EXPECT_NE(n, kf1);
  }
  EXPECT_TRUE(kf1->ordered_covisibles().empty());
  // Its points: those left with one (depth) observation go bad, the others lose one observation.
  for (std::size_t k = 0; k < pairs01.size(); ++k) {
    EXPECT_TRUE(pairs01[k]->is_bad());
    EXPECT_EQ(kf0->map_point(pairs01_idx[k]), nullptr);
  }
  for (MapPoint* mp : triples) {
    EXPECT_FALSE(mp->is_bad());
    EXPECT_FALSE(mp->is_in_keyframe(kf1));
    EXPECT_EQ(mp->num_observations(), 4);
    EXPECT_EQ(mp->reference_keyframe(), kf2);  // was kf1: moves to the first remaining observer
  }
  EXPECT_EQ(g.map.map_point_count(), points_before - (30 + 40 + 30 + 35));

  // The pose relative to the parent reproduces the original pose ...
  EXPECT_TRUE(resolve(kf1).isApprox(T1, 1e-12));
  EXPECT_TRUE((kf1->T_c_parent() * kf0->T_cw()).isApprox(T1, 1e-12));
  // ... also through a chain of removed keyframes (kf3 under kf2, kf2 under kf0) ...
  kf3->set_bad();
  kf2->set_bad();
  EXPECT_EQ(kf3->parent(), kf2);
  EXPECT_EQ(kf2->parent(), kf0);
  EXPECT_TRUE(resolve(kf3).isApprox(T3, 1e-12));
  EXPECT_TRUE(resolve(kf2).isApprox(T2, 1e-12));
  // The map's links give the same poses by id, bit for bit (they are what outlives the objects).
  for (KeyFrame* kf : {kf1, kf2, kf3})
    EXPECT_TRUE(g.map.resolve_pose(kf->id()).matrix() == resolve(kf).matrix());
  EXPECT_EQ(g.map.nearest_active_keyframe(kf3->id()), kf0);
  // ... and follows a correction of the live ancestor rigidly, after the removed keyframes are
  // freed (a participant that declares lets them go).
  const Eigen::Isometry3d T0 = kf0->T_cw();
  const Eigen::Isometry3d moved = lrd::test::pose(0.1, -0.2, 0.05, 0.3, 0.2, -0.1);
  kf0->set_pose(moved);
  const std::uint64_t id3 = kf3->id();
  lrd::map::ReclamationMembership member(g.map.reclamation(), "test");
  member.quiescent();
  EXPECT_EQ(g.map.memory().reclamation.freed_keyframes, 3u);
  EXPECT_EQ(g.map.memory().reclamation.waiting_keyframes, 0u);
  EXPECT_TRUE((g.map.resolve_pose(id3) * moved.inverse()).isApprox(T3 * T0.inverse(), 1e-9));
}

TEST(KeyFrameGraph, KeyFrameZeroAndProtectedKeyFramesAreNotRemoved) {
  Graph g;
  KeyFrame* kf0 = g.keyframe();
  KeyFrame* kf1 = g.keyframe();
  KeyFrame* kf2 = g.keyframe();
  const auto p = g.points(20, {kf0, kf1, kf2});
  kf1->update_connections();
  kf2->update_connections();
  kf0->set_bad();
  EXPECT_FALSE(kf0->is_bad());
  kf2->set_not_erase(true);
  kf2->set_bad();
  EXPECT_FALSE(kf2->is_bad());
  EXPECT_EQ(g.map.keyframe_count(), 3u);
  EXPECT_EQ(kf1->weight(kf2), 20);
  kf2->set_not_erase(false);
  kf2->set_bad();
  EXPECT_TRUE(kf2->is_bad());
  EXPECT_EQ(g.map.keyframe_count(), 2u);
  EXPECT_EQ(g.map.first_keyframe(), kf0);
  for (MapPoint* mp : p) EXPECT_EQ(mp->num_observations(), 4);
}

TEST(KeyFrameGraph, TrackedPointsAndSceneDepth) {
  Graph g;
  KeyFrame* kf0 = g.keyframe(lrd::test::pose(0.0, 0.0, 0.0, 0.0, 0.0, 1.0));  // camera 1 m behind the origin
  KeyFrame* kf1 = g.keyframe();
  for (int k = 1; k <= 9; ++k) g.point({kf0}, true, Eigen::Vector3d(0.1 * k, 0.0, k));  // depths 2..10 in kf0
  for (int k = 0; k < 4; ++k) g.point({kf0, kf1}, true, Eigen::Vector3d(0.0, 0.0, 3.5));
  MapPoint* gone = g.point({kf0, kf1}, true, Eigen::Vector3d(0.0, 0.0, 100.0));
  gone->set_bad();
  EXPECT_EQ(kf0->tracked_map_points(1), 13);
  EXPECT_EQ(kf0->tracked_map_points(3), 4);
  EXPECT_DOUBLE_EQ(kf0->scene_depth_quantile(0.0), 2.0);
  EXPECT_DOUBLE_EQ(kf0->scene_depth_quantile(0.5), 4.5);  // 2 3 4 4.5 4.5 4.5 4.5 5 6 7 8 9 10
  EXPECT_DOUBLE_EQ(kf0->scene_depth_quantile(1.0), 10.0);
  kf0->erase_map_point(gone);  // not in the keyframe any more: nothing happens
  MapPoint* some = kf1->map_points()[g.stereo[9]];
  ASSERT_NE(some, nullptr);
  kf1->erase_map_point(some);
  EXPECT_EQ(kf1->map_point(g.stereo[9]), nullptr);
  EXPECT_EQ(kf1->tracked_map_points(1), 3);
}

TEST(MapPoint, DistinctiveDescriptorIsTheMedoid) {
  Graph g;
  std::vector<KeyFrame*> kfs;
  for (int k = 0; k < 5; ++k) kfs.push_back(g.keyframe());
  // One observation per keyframe, each through its own keypoint, with hand-made descriptors:
  // A = 0, B and C and D each 8 bits away from A (16 from each other), E far from everyone.
  // Medians of the distances to all (self included): A 8, B/C/D 16, E about 190: A is the medoid.
  MapPoint* mp = g.map.create_map_point(Eigen::Vector3d(0, 0, 2), kfs[0], 0);
  cv::Mat desc = g.frame.descriptors();  // shares the keyframes' buffer
  auto set_bits = [&](std::size_t row, int from, int to) {
    std::uint8_t* r = desc.ptr<std::uint8_t>(static_cast<int>(row));
    std::fill(r, r + 32, std::uint8_t{0});
    for (int b = from; b < to; ++b) r[b / 8] |= static_cast<std::uint8_t>(1u << (b % 8));
  };
  const std::size_t idx[5] = {g.stereo[0], g.stereo[1], g.stereo[2], g.stereo[3], g.stereo[4]};
  set_bits(idx[0], 0, 8);     // B
  set_bits(idx[1], 56, 256);  // E
  set_bits(idx[2], 8, 16);    // C
  set_bits(idx[3], 0, 0);     // A, observed by the fourth keyframe
  set_bits(idx[4], 16, 24);   // D
  for (int k = 0; k < 5; ++k) {
    mp->add_observation(kfs[static_cast<std::size_t>(k)], idx[k]);
    kfs[static_cast<std::size_t>(k)]->add_map_point(mp, idx[k]);
  }
  mp->compute_distinctive_descriptor();
  ASSERT_EQ(mp->descriptor().rows, 1);
  ASSERT_EQ(mp->descriptor().cols, 32);
  EXPECT_EQ(cv::norm(mp->descriptor(), desc.row(static_cast<int>(idx[3])), cv::NORM_HAMMING), 0.0);
  // Without A, B C D form a triangle of 16s, and E is far: the first of B C D (by keyframe id).
  mp->erase_observation(kfs[3]);
  mp->compute_distinctive_descriptor();
  EXPECT_EQ(cv::norm(mp->descriptor(), desc.row(static_cast<int>(idx[0])), cv::NORM_HAMMING), 0.0);
  // A copy, not a view into the keyframe's descriptors.
  EXPECT_NE(mp->descriptor().data, desc.ptr(static_cast<int>(idx[0])));
}

TEST(MapPoint, ObservationsAreWeightedAndTooFewMakeThePointBad) {
  Graph g;
  ASSERT_GT(g.mono.size(), 50u);
  KeyFrame* kf0 = g.keyframe();
  KeyFrame* kf1 = g.keyframe();
  KeyFrame* kf2 = g.keyframe();
  KeyFrame* kf3 = g.keyframe();

  MapPoint* stereo3 = g.point({kf0, kf1, kf2});
  EXPECT_EQ(stereo3->num_observations(), 6);
  stereo3->add_observation(kf1, 0);  // already observed: ignored
  EXPECT_EQ(stereo3->num_observations(), 6);
  stereo3->erase_observation(kf2);
  EXPECT_EQ(stereo3->num_observations(), 4);
  EXPECT_FALSE(stereo3->is_bad());
  const std::size_t i = *stereo3->index_in(kf0);
  stereo3->erase_observation(kf1);  // 2 left: bad
  EXPECT_TRUE(stereo3->is_bad());
  EXPECT_TRUE(stereo3->observations().empty());
  EXPECT_EQ(stereo3->num_observations(), 0);
  EXPECT_EQ(kf0->map_point(i), nullptr);
  const auto live = g.map.map_points();
  EXPECT_EQ(std::count(live.begin(), live.end(), stereo3), 0);

  MapPoint* mono3 = g.point({kf0, kf1, kf2}, false);
  EXPECT_EQ(mono3->num_observations(), 3);
  mono3->erase_observation(kf3);  // not an observer: nothing changes
  EXPECT_EQ(mono3->num_observations(), 3);
  mono3->erase_observation(kf0);
  EXPECT_TRUE(mono3->is_bad());

  MapPoint* mono4 = g.point({kf0, kf1, kf2, kf3}, false);
  EXPECT_EQ(mono4->reference_keyframe(), kf0);
  mono4->erase_observation(kf0);
  EXPECT_FALSE(mono4->is_bad());
  EXPECT_EQ(mono4->num_observations(), 3);
  EXPECT_EQ(mono4->reference_keyframe(), kf1);

  // One observation with depth (2) and one without (1): 3, then 2 after losing the latter.
  MapPoint* mixed = g.map.create_map_point(Eigen::Vector3d(0, 0, 2), kf0, 0);
  const std::size_t s = g.stereo.at(g.next_stereo++), m = g.mono.at(g.next_mono++);
  mixed->add_observation(kf0, s);
  kf0->add_map_point(mixed, s);
  mixed->add_observation(kf1, m);
  kf1->add_map_point(mixed, m);
  EXPECT_EQ(mixed->num_observations(), 3);
  mixed->erase_observation(kf1);
  EXPECT_TRUE(mixed->is_bad());
  EXPECT_EQ(kf0->map_point(s), nullptr);  // the remaining observer's slot is cleared
}

TEST(MapPoint, ReplaceMovesObservationsToTheSurvivor) {
  Graph g;
  KeyFrame* kf0 = g.keyframe();
  KeyFrame* kf1 = g.keyframe();
  KeyFrame* kf2 = g.keyframe();
  MapPoint* p = g.point({kf0, kf1});
  MapPoint* q = g.point({kf1, kf2});
  const std::size_t p0 = *p->index_in(kf0), p1 = *p->index_in(kf1), q1 = *q->index_in(kf1);
  const std::size_t map_before = g.map.map_point_count();
  p->increase_visible(3);
  p->increase_found(2);
  p->replace(q);
  EXPECT_TRUE(p->is_bad());
  EXPECT_EQ(p->replaced_by(), q);
  EXPECT_TRUE(p->observations().empty());
  // kf0 sees q through p's keypoint; kf1, which saw both, keeps q's keypoint and drops p's.
  EXPECT_EQ(kf0->map_point(p0), q);
  EXPECT_EQ(q->index_in(kf0), p0);
  EXPECT_EQ(kf1->map_point(p1), nullptr);
  EXPECT_EQ(kf1->map_point(q1), q);
  EXPECT_EQ(q->index_in(kf1), q1);
  EXPECT_TRUE(q->is_in_keyframe(kf2));
  EXPECT_EQ(q->num_observations(), 6);
  EXPECT_EQ(q->found(), 1 + 3);                    // 1 + p's 1 + 2
  EXPECT_FLOAT_EQ(q->found_ratio(), 4.0f / 5.0f);  // visible 1 + p's 1 + 3
  EXPECT_EQ(g.map.map_point_count(), map_before - 1);
  // Replacing with itself, or a bad point, does nothing.
  const auto obs = q->observations();
  q->replace(q);
  EXPECT_FALSE(q->is_bad());
  EXPECT_EQ(q->observations(), obs);
  p->replace(q);
  EXPECT_EQ(q->num_observations(), 6);
}

TEST(Map, IdsOrderAndLifetime) {
  Graph g;
  KeyFrame* kf0 = g.keyframe();
  KeyFrame* kf1 = g.keyframe();
  KeyFrame* kf2 = g.keyframe();
  EXPECT_EQ(kf0->id(), 0u);
  EXPECT_EQ(kf2->id(), 2u);
  EXPECT_EQ(g.map.first_keyframe(), kf0);
  EXPECT_EQ(g.map.keyframes(), (std::vector<KeyFrame*>{kf0, kf1, kf2}));
  const auto pts = g.points(5, {kf0, kf1, kf2});
  for (std::size_t k = 0; k < pts.size(); ++k) EXPECT_EQ(pts[k]->id(), k);
  EXPECT_EQ(g.map.map_points(), pts);
  pts[2]->set_bad();
  EXPECT_EQ(g.map.map_point_count(), 4u);
  EXPECT_EQ(g.map.map_points(), (std::vector<MapPoint*>{pts[0], pts[1], pts[3], pts[4]}));
  EXPECT_EQ(g.map.create_map_point(Eigen::Vector3d::Zero(), kf0, 0)->id(), 5u);
  // Removed objects stay allocated until a participant declares: without one, never.
  EXPECT_TRUE(pts[2]->is_bad());
  EXPECT_EQ(g.map.memory().reclamation.waiting_map_points, 1u);
  EXPECT_EQ(g.map.memory().reclamation.freed_map_points, 0u);
  EXPECT_EQ(g.map.keyframe(1), kf1);
  EXPECT_EQ(g.map.keyframe(7), nullptr);
}

TEST(MapPoint, RemovalClearsEverySlotOfItsObserversIncludingASecondOne) {
  // Tracking can match one point to two keypoints of a frame; the keyframe made from it keeps both
  // slots while the point records one observation. A removed point must leave neither slot behind
  // (it is freed once no thread holds it: map/reclamation.h).
  Graph g;
  KeyFrame* kf0 = g.keyframe();
  KeyFrame* kf1 = g.keyframe();
  MapPoint* p = g.point({kf0, kf1});
  MapPoint* q = g.point({kf0, kf1});
  MapPoint* r = g.point({kf0, kf1});
  const std::size_t spare = g.stereo.at(g.next_stereo++);
  const std::size_t spare2 = g.stereo.at(g.next_stereo++);
  kf1->add_map_point(p, spare);  // a second slot, no second observation
  kf1->add_map_point(q, spare2);
  ASSERT_NE(p->index_in(kf1), std::optional<std::size_t>(spare));
  p->set_bad();
  for (MapPoint* slot : kf1->map_points()) EXPECT_NE(slot, p);
  EXPECT_EQ(kf1->map_point(spare), nullptr);
  // Replaced: the observed slot goes to the survivor, the second one is cleared.
  q->replace(r);
  for (MapPoint* slot : kf1->map_points()) EXPECT_NE(slot, q);
  EXPECT_EQ(kf1->map_point(spare2), nullptr);
  EXPECT_EQ(r->num_observations(), 4);
}

TEST(KeyFrameGraph, RemovalErasesOneSidedEdgesToo) {
  // An edge can be one-sided: a keyframe counted another when they shared more points than the
  // other counts now. A removed keyframe is freed later, so no keyframe may keep it as a neighbour.
  Graph g;
  KeyFrame* kf0 = g.keyframe();
  KeyFrame* kf1 = g.keyframe();
  KeyFrame* kf2 = g.keyframe();
  g.points(20, {kf0, kf1});
  g.points(20, {kf1, kf2});
  kf1->update_connections();
  kf2->update_connections();
  kf0->add_connection(kf2, 30);  // kf2 does not list kf0
  ASSERT_EQ(kf2->weight(kf0), 0);
  ASSERT_EQ(kf0->weight(kf2), 30);
  kf2->set_bad();
  ASSERT_TRUE(kf2->is_bad());
  EXPECT_EQ(kf0->weight(kf2), 0);
  EXPECT_EQ(kf1->weight(kf2), 0);
  for (KeyFrame* kf : {kf0, kf1})
    for (KeyFrame* n : kf->ordered_covisibles()) EXPECT_NE(n, kf2);
}
