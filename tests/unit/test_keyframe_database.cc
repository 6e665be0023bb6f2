// The keyframe database (place recognition's inverse index) on hand-made bags of words, so that
// every score is known exactly (Vocabulary::score of two vectors is the sum over their common
// words of the smaller weight): which older keyframes are loop candidates (never the query's
// connected keyframes, nor newer ones), the shared-word and minimum-score filters, the group
// score that prefers a place seen consistently over one lucky view, relocalization candidates,
// and removed keyframes. Keyframes are copies of one rendered frame; covisibility comes from
// hand-made shared map points.
#include <gtest/gtest.h>

#include <vector>

#include "lrd/map/keyframe_database.h"
#include "lrd/map/map.h"
#include "lrd/place/vocabulary.h"
#include "textured_plane.h"

using lrd::data::Frame;
using lrd::map::KeyFrame;
using lrd::map::KeyFrameDatabase;
using lrd::place::BowVector;
using lrd::place::Vocabulary;

namespace {

const Frame& base_frame() {
  static const Frame frame = [] {
    lrd::test::TexturedPlane plane;
    return plane.frame(0, Eigen::Isometry3d::Identity());
  }();
  return frame;
}

// Words `first` .. `first + n - 1`, each of weight `w`, plus one filler word (id `filler`) that
// takes the rest of the unit L1 mass (none when the words already make 1).
BowVector bow(lrd::place::WordId first, int n, double w, lrd::place::WordId filler = 0) {
  BowVector v;
  for (int i = 0; i < n; ++i) v[first + static_cast<lrd::place::WordId>(i)] = w;
  const double rest = 1.0 - n * w;
  if (rest > 1e-12) v[filler] = rest;
  return v;
}

struct Places {
  lrd::map::Map map;
  KeyFrameDatabase db;
  std::size_t next_index = 0;

  KeyFrame* keyframe(const BowVector& words, bool indexed = true) {
    Frame f = base_frame();
    f.bow = words;
    KeyFrame* kf = map.create_keyframe(f);
    if (indexed) db.add(kf);
    return kf;
  }
  // `n` map points seen by every keyframe of `kfs`, then their covisibility updated.
  void link(const std::vector<KeyFrame*>& kfs, int n) {
    for (int k = 0; k < n; ++k) {
      const std::size_t idx = next_index++;
      lrd::map::MapPoint* mp = map.create_map_point(Eigen::Vector3d(0.0, 0.0, 2.0), kfs.front(), 0);
      for (KeyFrame* kf : kfs) {
        mp->add_observation(kf, idx);
        kf->add_map_point(mp, idx);
      }
    }
    for (KeyFrame* kf : kfs) kf->update_connections();
  }
};

// The query: words 1000 .. 1009, 0.1 each.
BowVector query_words() {
  return bow(1000, 10, 0.1);
}

}  // namespace

TEST(KeyFrameDatabase, LoopCandidatesAreOlderKeyFramesNotConnectedToTheQuery) {
  Places p;
  KeyFrame* same_old = p.keyframe(query_words());        // 0: the place, long ago
  KeyFrame* same_connected = p.keyframe(query_words());  // 1: the place, but shares a point with the query
  KeyFrame* other = p.keyframe(bow(2000, 10, 0.1));      // 2: elsewhere
  KeyFrame* weak = p.keyframe(query_words());            // 3: one shared point only (a weak link)
  KeyFrame* query = p.keyframe(query_words());           // 4
  KeyFrame* newer = p.keyframe(query_words());           // 5: indexed after the query
  p.link({same_connected, query}, 20);
  p.link({weak, query}, 1);
  ASSERT_EQ(query->weight(weak), 1);  // below the covisibility threshold, still connected
  ASSERT_EQ(p.db.size(), 6u);
  ASSERT_DOUBLE_EQ(Vocabulary::score(query->bow(), same_old->bow()), 1.0);
  ASSERT_DOUBLE_EQ(Vocabulary::score(query->bow(), other->bow()), 0.0);

  EXPECT_EQ(p.db.loop_candidates(query, 0.0), std::vector<KeyFrame*>{same_old});
  // Asked again (a new query number): the same answer.
  EXPECT_EQ(p.db.loop_candidates(query, 0.5), std::vector<KeyFrame*>{same_old});
  // For the newest keyframe nothing is connected: every view of the place scores 1.0, and the
  // three linked ones make groups of 2.0 (with the query's 1.0 as neighbour, weak link
  // included), which leave the lone old view (1.0 < 0.75 * 2.0) out.
  EXPECT_EQ(p.db.loop_candidates(newer, 0.0), (std::vector<KeyFrame*>{same_connected, weak, query}));
}

TEST(KeyFrameDatabase, SharedWordsAndMinimumScoreFilterTheCandidates) {
  Places p;
  (void)p.keyframe(bow(9000, 10, 0.1));  // keyframe 0, which is never removed
  // Scores against the query: full 1.0; eight 0.8 (8 of the 10 words); seven 0.7 (7 words, below
  // 80 % of the best count of shared words: never scored); light 0.5 (10 words at 0.05).
  KeyFrame* full = p.keyframe(query_words());
  KeyFrame* eight = p.keyframe(bow(1000, 8, 0.1, 3000));
  KeyFrame* seven = p.keyframe(bow(1000, 7, 0.1, 3001));
  KeyFrame* light = p.keyframe(bow(1000, 10, 0.05, 3002));
  KeyFrame* query = p.keyframe(query_words());
  ASSERT_NEAR(Vocabulary::score(query->bow(), eight->bow()), 0.8, 1e-12);
  ASSERT_NEAR(Vocabulary::score(query->bow(), seven->bow()), 0.7, 1e-12);
  ASSERT_NEAR(Vocabulary::score(query->bow(), light->bow()), 0.5, 1e-12);

  // Unlinked, each keyframe is its own group: groups within 75 % of the best (1.0), best first.
  EXPECT_EQ(p.db.loop_candidates(query, 0.0), (std::vector<KeyFrame*>{full, eight}));
  // The minimum score removes keyframes before any grouping.
  EXPECT_EQ(p.db.loop_candidates(query, 0.9), std::vector<KeyFrame*>{full});
  EXPECT_TRUE(p.db.loop_candidates(query, 1.01).empty());
  // Without the best one, the next best sets the bar: eight (0.8) and light (0.5 < 0.6) -> eight;
  // seven still fails the shared-word count (7 < 8).
  full->set_bad();
  EXPECT_EQ(p.db.loop_candidates(query, 0.0), std::vector<KeyFrame*>{eight});
  eight->set_bad();
  // Now light shares the most words (10): seven (7 < 8) stays out, light is alone.
  EXPECT_EQ(p.db.loop_candidates(query, 0.0), std::vector<KeyFrame*>{light});
}

TEST(KeyFrameDatabase, AGroupSeenConsistentlyBeatsOneLuckyView) {
  // A lone keyframe scoring 0.9, and three covisible keyframes of another place scoring 0.6,
  // 0.7 and 0.6: as separate groups the lone one wins; once the three are covisible their group
  // (1.9) leaves the lone one (0.9 < 0.75 * 1.9) out, and the group's best keyframe stands for it.
  for (const bool linked : {false, true}) {
    SCOPED_TRACE(linked ? "covisible group" : "no covisibility");
    Places p;
    KeyFrame* g1 = p.keyframe(bow(1000, 10, 0.06, 4000));
    KeyFrame* g2 = p.keyframe(bow(1000, 10, 0.07, 4001));
    KeyFrame* g3 = p.keyframe(bow(1000, 10, 0.06, 4002));
    KeyFrame* lone = p.keyframe(bow(1000, 10, 0.09, 4003));
    KeyFrame* query = p.keyframe(query_words());
    if (linked) {
      p.link({g1, g2, g3}, 30);
      ASSERT_EQ(g1->ordered_covisibles(), (std::vector<KeyFrame*>{g2, g3}));
    }
    ASSERT_NEAR(Vocabulary::score(query->bow(), lone->bow()), 0.9, 1e-12);
    ASSERT_NEAR(Vocabulary::score(query->bow(), g2->bow()), 0.7, 1e-12);
    const auto candidates = p.db.loop_candidates(query, 0.0);
    if (linked) {
      EXPECT_EQ(candidates, std::vector<KeyFrame*>{g2});
    } else {
      // 0.9, then 0.7 (>= 0.675); the 0.6 ones fall under 75 % of 0.9.
      EXPECT_EQ(candidates, (std::vector<KeyFrame*>{lone, g2}));
    }
  }
}

TEST(KeyFrameDatabase, RelocalizationCandidatesSkipRemovedKeyFramesAndClearEmpties) {
  Places p;
  KeyFrame* k0 = p.keyframe(bow(2000, 10, 0.1));  // elsewhere
  KeyFrame* k1 = p.keyframe(query_words());
  KeyFrame* k2 = p.keyframe(bow(1000, 9, 0.1, 5000));  // 0.9
  KeyFrame* k3 = p.keyframe(query_words());
  p.link({k1, k2}, 20);
  Frame frame = base_frame();
  frame.bow = query_words();
  // k1 and k2 make a group of 1.0 + 0.9 whose best is k1 (for both of them); k3 alone (1.0)
  // is under 75 % of 1.9.
  EXPECT_EQ(p.db.relocalization_candidates(frame), std::vector<KeyFrame*>{k1});
  k1->set_bad();  // k2 loses its covisible neighbour: alone, 0.9
  EXPECT_EQ(p.db.relocalization_candidates(frame), (std::vector<KeyFrame*>{k3, k2}));
  (void)k0;
  p.db.clear();
  EXPECT_EQ(p.db.size(), 0u);
  EXPECT_TRUE(p.db.relocalization_candidates(frame).empty());
  // Indexed again after the clear: found again.
  p.db.add(k3);
  EXPECT_EQ(p.db.relocalization_candidates(frame), std::vector<KeyFrame*>{k3});
}
