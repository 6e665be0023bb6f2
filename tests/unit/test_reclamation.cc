// Deferred reclamation (map/reclamation.h): a removed object is freed only once every active
// participant has declared a quiescent moment after its removal; leaving counts as letting go;
// a newcomer does not hold back what was removed before it came; without participants nothing is
// ever freed (code holding the map mutex may still look at what it just removed).
#include <gtest/gtest.h>

#include <memory>

#include "lrd/map/keyframe.h"
#include "lrd/map/map_point.h"
#include "lrd/map/reclamation.h"

using lrd::map::MapPoint;
using lrd::map::Reclamation;

namespace {

std::unique_ptr<MapPoint> point(std::uint64_t id) {
  return std::make_unique<MapPoint>(id, Eigen::Vector3d::Zero(), nullptr, 0, nullptr);
}

}  // namespace

TEST(Reclamation, FreesOnlyAfterEveryActiveParticipantDeclared) {
  Reclamation r;
  const auto a = r.join("a");
  const auto b = r.join("b");
  r.retire(point(0));
  r.quiescent(a);
  EXPECT_EQ(r.stats().freed_map_points, 0u);
  EXPECT_EQ(r.stats().waiting_map_points, 1u);
  r.quiescent(a);  // one participant declaring twice is not enough
  EXPECT_EQ(r.stats().freed_map_points, 0u);
  r.quiescent(b);
  EXPECT_EQ(r.stats().freed_map_points, 1u);
  EXPECT_EQ(r.stats().waiting_map_points, 0u);
}

TEST(Reclamation, ARemovalAfterADeclarationWaitsForTheNextOne) {
  Reclamation r;
  const auto a = r.join("a");
  const auto b = r.join("b");
  r.quiescent(a);
  r.retire(point(0));  // after a's declaration: a may hold it
  r.quiescent(b);
  EXPECT_EQ(r.stats().freed_map_points, 0u);
  r.retire(point(1));  // after b's declaration too
  r.quiescent(a);
  EXPECT_EQ(r.stats().freed_map_points, 1u);  // point 0 only: b may still hold point 1
  EXPECT_EQ(r.stats().waiting_map_points, 1u);
  r.quiescent(b);
  EXPECT_EQ(r.stats().freed_map_points, 2u);
}

TEST(Reclamation, LeavingLetsGoAndNewcomersDoNotHoldBack) {
  Reclamation r;
  const auto a = r.join("a");
  r.retire(point(0));
  const auto b = r.join("b");  // joined after the removal: holds nothing of it
  r.quiescent(a);
  EXPECT_EQ(r.stats().freed_map_points, 1u);
  r.retire(point(1));
  r.leave(a);
  EXPECT_EQ(r.stats().freed_map_points, 1u);  // b still active
  r.leave(b);
  EXPECT_EQ(r.stats().freed_map_points, 2u);
}

TEST(Reclamation, WithoutParticipantsNothingIsFreed) {
  Reclamation r;
  r.retire(point(0));
  r.retire(point(1));
  EXPECT_EQ(r.stats().freed_map_points, 0u);
  EXPECT_EQ(r.stats().waiting_map_points, 2u);
}

TEST(Reclamation, MembershipJoinsAndLeaves) {
  Reclamation r;
  const auto other = r.join("other");
  {
    lrd::map::ReclamationMembership m(r, "scoped");
    r.retire(point(0));
    r.quiescent(other);
    EXPECT_EQ(r.stats().freed_map_points, 0u);  // the scoped member may hold it
  }
  EXPECT_EQ(r.stats().freed_map_points, 1u);
}
