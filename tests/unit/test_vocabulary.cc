// The bag-of-words vocabulary: deterministic training, the file format (round trip, errors),
// transform and the L1 score, and that two views of one textured scene score higher than views
// of different scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>
#include <set>
#include <string>
#include <vector>

#include "error_of.h"
#include "lrd/features/orb_extractor.h"
#include "lrd/place/vocabulary.h"
#include "lrd/util/error.h"
#include "temp_dir.h"

using lrd::place::BowVector;
using lrd::place::FeatureVector;
using lrd::place::Vocabulary;
using lrd::place::VocabularyParams;
using lrd::test::error_of;
using lrd::test::TempDir;

namespace {

constexpr int kWidth = 480, kHeight = 360;

// Fractal noise: octaves of cubic-upsampled random grids, 32 down to 2 pixels, amplitude
// `amp` at the coarsest.
cv::Mat fractal_noise(cv::RNG& rng, float amp) {
  cv::Mat acc(kHeight, kWidth, CV_32F, cv::Scalar(0)), grid, up;
  for (int cell = 32; cell >= 2; cell /= 2, amp *= 0.7f) {
    grid.create(kHeight / cell + 2, kWidth / cell + 2, CV_32F);
    rng.fill(grid, cv::RNG::UNIFORM, -amp, amp);
    cv::resize(grid, up, cv::Size(grid.cols * cell, grid.rows * cell), 0, 0, cv::INTER_CUBIC);
    acc += up(cv::Rect(cell, cell, kWidth, kHeight));
  }
  return acc;
}

// A scene: random polygons, rectangles and discs over fractal noise, each filled with noise of
// its own (as the textured plane of textured_plane.h, but flat shapes alone give corners that
// look alike in every scene). Different seeds give scenes of the same statistics, told apart
// only by their layout: harder than real places, which also differ in kind.
cv::Mat texture(std::uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat t = fractal_noise(rng, 40.0f) + 128.0f;
  const cv::Mat fill = fractal_noise(rng, 30.0f);
  for (int k = 0; k < 300; ++k) {
    const int size = k < 40 ? rng.uniform(20, 50) : rng.uniform(5, 20);
    const cv::Point c(rng.uniform(0, kWidth), rng.uniform(0, kHeight));
    // Drawn into a mask of the shape's box only.
    const cv::Rect box = cv::Rect(c.x - size - 1, c.y - size - 1, 2 * size + 6, 2 * size + 6) &
                         cv::Rect(0, 0, kWidth, kHeight);
    cv::Mat mask(box.size(), CV_8U, cv::Scalar(0));
    const cv::Point o = c - box.tl();
    switch (rng.uniform(0, 3)) {
      case 0: {
        std::vector<cv::Point> poly;
        const int n = rng.uniform(3, 6);
        for (int j = 0; j < n; ++j)
          poly.emplace_back(o.x + rng.uniform(-size, size + 1), o.y + rng.uniform(-size, size + 1));
        cv::fillConvexPoly(mask, poly, cv::Scalar(255));
        break;
      }
      case 1:
        cv::rectangle(mask, cv::Rect(o.x, o.y, rng.uniform(3, size + 4), rng.uniform(3, size + 4)),
                      cv::Scalar(255), cv::FILLED);
        break;
      default:
        cv::circle(mask, o, std::max(2, size / 2), cv::Scalar(255), cv::FILLED);
    }
    const cv::Mat shape = fill(box) + static_cast<float>(rng.uniform(20, 236));
    shape.copyTo(t(box), mask);
  }
  cv::GaussianBlur(t, t, cv::Size(0, 0), 0.7);
  cv::Mat out;
  t.convertTo(out, CV_8U);
  return out;
}

// The same scene seen again: rotated by 3 degrees, scaled by 1.04 and shifted.
cv::Mat other_view(const cv::Mat& img) {
  cv::Mat m = cv::getRotationMatrix2D(cv::Point2f(kWidth / 2.0f, kHeight / 2.0f), 3.0, 1.04);
  m.at<double>(0, 2) += 14.0;
  m.at<double>(1, 2) -= 9.0;
  cv::Mat out;
  cv::warpAffine(img, out, m, img.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  return out;
}

cv::Mat orb_descriptors(const cv::Mat& grey, int features) {
  lrd::features::OrbParams params;
  params.n_features = features;
  lrd::features::OrbExtractor orb(params);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat d;
  orb.extract(grey, cv::Mat(), keypoints, d);
  return d;
}

// 1000 descriptors from each of 15 training scenes (seeds 100 ..), made once per process.
const std::vector<cv::Mat>& training_descriptors() {
  static const std::vector<cv::Mat> d = [] {
    std::vector<cv::Mat> out;
    for (std::uint64_t s = 100; s < 115; ++s) out.push_back(orb_descriptors(texture(s), 1000));
    return out;
  }();
  return d;
}

// k 10, 5 levels: about 12000 words from 15000 descriptors.
const Vocabulary& trained() {
  static const Vocabulary v = Vocabulary::train(training_descriptors(), VocabularyParams{});
  return v;
}

// Random 256-bit descriptors, for tests that need no ORB.
cv::Mat random_descriptors(int rows, std::uint64_t seed) {
  cv::Mat d(rows, 32, CV_8U);
  cv::RNG(seed).fill(d, cv::RNG::UNIFORM, 0, 256);
  return d;
}

// A small vocabulary of random descriptors (k 8, 3 levels), cheap to make.
const Vocabulary& small() {
  static const Vocabulary v = [] {
    std::vector<cv::Mat> images;
    for (std::uint64_t s = 0; s < 8; ++s) images.push_back(random_descriptors(400, s));
    VocabularyParams p;
    p.k = 8;
    p.levels = 3;
    return Vocabulary::train(images, p);
  }();
  return v;
}

}  // namespace

TEST(Vocabulary, TrainingIsDeterministicAndSeedMatters) {
  const std::vector<cv::Mat> images(training_descriptors().begin(), training_descriptors().begin() + 5);
  TempDir dir("vocab");
  const auto a = dir.path() / "a.lrdv", b = dir.path() / "b.lrdv", c = dir.path() / "c.lrdv";
  Vocabulary::train(images, VocabularyParams{}).save(a);
  Vocabulary::train(images, VocabularyParams{}).save(b);
  VocabularyParams other;
  other.seed = 12345;
  Vocabulary::train(images, other).save(c);
  const std::string bytes = TempDir::read(a);
  EXPECT_GT(bytes.size(), 100000u);
  EXPECT_EQ(bytes, TempDir::read(b));
  EXPECT_NE(bytes, TempDir::read(c));
}

TEST(Vocabulary, LoadSharedLoadsAFileOncePerProcessWhileItIsHeld) {
  const std::vector<cv::Mat> images(training_descriptors().begin(), training_descriptors().begin() + 5);
  TempDir dir("vocab_shared");
  const auto file = dir.path() / "v.lrdv";
  Vocabulary::train(images, VocabularyParams{}).save(file);
  auto first = Vocabulary::load_shared(file);
  // The same file by another spelling of its path: the same object.
  auto again = Vocabulary::load_shared(dir.path() / "." / "v.lrdv");
  EXPECT_EQ(first.get(), again.get());
  EXPECT_EQ(first->fingerprint(), Vocabulary::load(file).fingerprint());
  EXPECT_THROW(Vocabulary::load_shared(dir.path() / "missing.lrdv"), lrd::Error);
}

TEST(Vocabulary, TreeShape) {
  const Vocabulary& v = trained();
  EXPECT_FALSE(v.empty());
  EXPECT_EQ(v.k(), 10);
  EXPECT_EQ(v.levels(), 5);
  std::size_t descriptors = 0;
  for (const cv::Mat& d : training_descriptors()) descriptors += static_cast<std::size_t>(d.rows);
  EXPECT_GT(descriptors, 14000u);
  // Deep enough for nearly one word per descriptor; a leaf is never empty.
  EXPECT_GT(v.word_count(), descriptors / 2);
  EXPECT_LE(v.word_count(), descriptors);
  EXPECT_GT(v.node_count(), v.word_count() + 10);
  // idf = ln(15 / n), n in [1, 15].
  double max_idf = 0.0;
  for (std::size_t w = 0; w < v.word_count(); ++w) {
    const double idf = v.word_weight(static_cast<lrd::place::WordId>(w));
    EXPECT_GE(idf, 0.0);
    max_idf = std::max(max_idf, idf);
  }
  EXPECT_NEAR(max_idf, std::log(15.0), 1e-12);
  EXPECT_THROW((void)v.word_weight(static_cast<lrd::place::WordId>(v.word_count())), lrd::Error);
  EXPECT_TRUE(Vocabulary().empty());
  EXPECT_EQ(Vocabulary().word_count(), 0u);
}

TEST(Vocabulary, FewDistinctDescriptorsGiveOneWordEach) {
  // Three distinct descriptors, many times over: one word each, whatever k and levels.
  const cv::Mat d = random_descriptors(3, 5);
  cv::Mat many;
  for (int i = 0; i < 20; ++i) many.push_back(d);
  VocabularyParams p;
  p.k = 2;
  p.levels = 4;
  const Vocabulary v = Vocabulary::train({many, d.rowRange(0, 1)}, p);
  EXPECT_EQ(v.word_count(), 3u);
  std::set<lrd::place::WordId> words;
  for (int r = 0; r < 3; ++r) words.insert(v.word_of(d.ptr<std::uint8_t>(r)));
  EXPECT_EQ(words.size(), 3u);
  // Row 0 is in both images: idf ln(2/2) = 0, a stop word left out of the BoW vector.
  EXPECT_EQ(v.word_weight(v.word_of(d.ptr<std::uint8_t>(0))), 0.0);
  EXPECT_NEAR(v.word_weight(v.word_of(d.ptr<std::uint8_t>(1))), std::log(2.0), 1e-15);
  BowVector bow;
  v.transform(d, bow);
  ASSERT_EQ(bow.size(), 2u);
  EXPECT_EQ(bow.count(v.word_of(d.ptr<std::uint8_t>(0))), 0u);
  EXPECT_NEAR(bow.begin()->second, 0.5, 1e-15);
}

TEST(Vocabulary, RejectsBadInput) {
  const std::vector<cv::Mat> d{random_descriptors(50, 1)};
  VocabularyParams p;
  p.k = 1;
  EXPECT_NE(error_of([&] { (void)Vocabulary::train(d, p); }).find("k = 1"), std::string::npos);
  p = VocabularyParams{};
  p.levels = 0;
  EXPECT_NE(error_of([&] { (void)Vocabulary::train(d, p); }).find("levels = 0"), std::string::npos);
  EXPECT_NE(
      error_of([&] { (void)Vocabulary::train({cv::Mat()}, VocabularyParams{}); }).find("no descriptors"),
      std::string::npos);
  const cv::Mat wide(4, 64, CV_8U, cv::Scalar(0));
  EXPECT_NE(error_of([&] { (void)Vocabulary::train({wide}, VocabularyParams{}); }).find("32 columns"),
            std::string::npos);
  BowVector bow;
  EXPECT_THROW(small().transform(cv::Mat(4, 32, CV_32F, cv::Scalar(0)), bow), lrd::Error);
  EXPECT_THROW((void)Vocabulary().word_of(d[0].ptr<std::uint8_t>(0)), lrd::Error);
  TempDir dir("vocab");
  const auto empty_file = dir.path() / "empty.lrdv";
  EXPECT_NE(error_of([&] { Vocabulary().save(empty_file); }).find(empty_file.string()), std::string::npos);
  const auto unwritable = dir.path() / "no" / "such" / "folder" / "v.lrdv";
  EXPECT_NE(error_of([&] { small().save(unwritable); }).find(unwritable.string()), std::string::npos);
  // An empty vocabulary transforms to nothing.
  FeatureVector fv;
  Vocabulary().transform(d[0], bow, fv, 1);
  EXPECT_TRUE(bow.empty());
  EXPECT_TRUE(fv.empty());
}

TEST(Vocabulary, TransformGivesNormalisedBowAndDirectIndex) {
  const Vocabulary& v = small();  // k 8, 3 levels
  const cv::Mat d = random_descriptors(300, 99);
  for (int levels_up : {-3, 0, 1, 2, 9}) {
    BowVector bow;
    FeatureVector fv;
    v.transform(d, bow, fv, levels_up);
    double sum = 0.0;
    for (const auto& [w, weight] : bow) {
      EXPECT_GT(weight, 0.0);
      EXPECT_LT(w, v.word_count());
      sum += weight;
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
    // Every row under exactly one node, rows increasing within a node.
    std::vector<int> seen(static_cast<std::size_t>(d.rows), 0);
    for (const auto& [node, rows] : fv) {
      EXPECT_LT(node, v.node_count());
      EXPECT_TRUE(std::is_sorted(rows.begin(), rows.end()));
      for (std::uint32_t r : rows) ++seen.at(r);
    }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; }));
    const int clamped = std::clamp(levels_up, 0, 2);
    if (clamped == 2) {
      EXPECT_LE(fv.size(), 8u);  // the root's children
    } else if (clamped == 1) {
      EXPECT_GT(fv.size(), 8u);
      EXPECT_LE(fv.size(), 64u);
    } else {
      // At the leaves: rows of one node share one word, and there is a node per word.
      std::set<lrd::place::WordId> words;
      for (const auto& [node, rows] : fv) {
        for (std::uint32_t r : rows)
          EXPECT_EQ(v.word_of(d.ptr<std::uint8_t>(static_cast<int>(r))),
                    v.word_of(d.ptr<std::uint8_t>(rows[0])));
        words.insert(v.word_of(d.ptr<std::uint8_t>(rows[0])));
      }
      EXPECT_EQ(words.size(), fv.size());
    }
    BowVector plain;
    v.transform(d, plain);
    EXPECT_EQ(plain, bow);
  }
  // tf-idf by hand for one word.
  BowVector bow;
  v.transform(d, bow);
  std::map<lrd::place::WordId, int> count;
  for (int r = 0; r < d.rows; ++r) ++count[v.word_of(d.ptr<std::uint8_t>(r))];
  double total = 0.0;
  for (const auto& [w, n] : count) total += n * v.word_weight(w);
  const auto& [w0, weight0] = *bow.begin();
  EXPECT_NEAR(weight0, count[w0] * v.word_weight(w0) / total, 1e-12);

  v.transform(cv::Mat(), bow);
  EXPECT_TRUE(bow.empty());
}

TEST(Vocabulary, SaveLoadRoundTrip) {
  TempDir dir("vocab");
  const auto file = dir.path() / "v.lrdv", again = dir.path() / "again.lrdv";
  small().save(file);
  const Vocabulary loaded = Vocabulary::load(file);
  EXPECT_EQ(loaded.k(), small().k());
  EXPECT_EQ(loaded.levels(), small().levels());
  EXPECT_EQ(loaded.node_count(), small().node_count());
  EXPECT_EQ(loaded.word_count(), small().word_count());
  EXPECT_EQ(TempDir::read(file).size(), 28u + 48u * small().node_count());
  for (std::uint64_t s : {1, 2}) {
    const cv::Mat d = random_descriptors(200, s + 1000);
    BowVector a, b;
    FeatureVector fa, fb;
    small().transform(d, a, fa, 1);
    loaded.transform(d, b, fb, 1);
    EXPECT_FALSE(a.empty());
    EXPECT_EQ(a, b);
    EXPECT_EQ(fa, fb);
  }
  for (std::size_t w = 0; w < small().word_count(); ++w) {
    const auto id = static_cast<lrd::place::WordId>(w);
    EXPECT_EQ(loaded.word_weight(id), small().word_weight(id));
  }
  loaded.save(again);
  EXPECT_EQ(TempDir::read(file), TempDir::read(again));
}

TEST(Vocabulary, LoadErrorsNameTheFile) {
  TempDir dir("vocab");
  const auto missing = dir.path() / "missing.lrdv";
  EXPECT_NE(error_of([&] { (void)Vocabulary::load(missing); }).find(missing.string()), std::string::npos);

  const auto garbage = dir.write("garbage.lrdv", "this is not a vocabulary at all, just some text\n");
  const std::string g = error_of([&] { (void)Vocabulary::load(garbage); });
  EXPECT_NE(g.find(garbage.string()), std::string::npos);
  EXPECT_NE(g.find("magic"), std::string::npos) << g;

  const auto good = dir.path() / "good.lrdv";
  small().save(good);
  const std::string bytes = TempDir::read(good);
  for (std::size_t cut : {std::size_t{0}, std::size_t{5}, std::size_t{20}, bytes.size() - 10}) {
    const auto truncated = dir.write("truncated.lrdv", bytes.substr(0, cut));
    const std::string t = error_of([&] { (void)Vocabulary::load(truncated); });
    EXPECT_NE(t.find(truncated.string()), std::string::npos);
    EXPECT_NE(t.find("truncated"), std::string::npos) << t;
  }

  std::string v2 = bytes;
  v2[8] = 2;  // version
  const auto bad_version = dir.write("version.lrdv", v2);
  const std::string bv = error_of([&] { (void)Vocabulary::load(bad_version); });
  EXPECT_NE(bv.find(bad_version.string()), std::string::npos);
  EXPECT_NE(bv.find("version 2"), std::string::npos) << bv;

  std::string k1 = bytes;
  k1[12] = 1;  // k
  const auto bad_k = dir.write("k.lrdv", k1);
  EXPECT_NE(error_of([&] { (void)Vocabulary::load(bad_k); }).find("bad k = 1"), std::string::npos);

  std::string loop = bytes;
  loop[28 + 48 * 2] = 5;  // node 2's parent: a later node
  const auto bad_tree = dir.write("tree.lrdv", loop);
  EXPECT_NE(error_of([&] { (void)Vocabulary::load(bad_tree); }).find("node 2 has parent 5"),
            std::string::npos);

  std::string word = bytes;
  word[28 + 48 * 1 + 4] = 0;  // node 1 (inner) given word id 0xffffff00
  const auto bad_word = dir.write("word.lrdv", word);
  EXPECT_NE(error_of([&] { (void)Vocabulary::load(bad_word); }).find(bad_word.string()), std::string::npos);

  const auto longer = dir.write("longer.lrdv", bytes + "xx");
  EXPECT_NE(error_of([&] { (void)Vocabulary::load(longer); }).find("2 bytes after"), std::string::npos);

  EXPECT_NE(error_of([&] { (void)Vocabulary::load(dir.path()); }).find(dir.path().string()),
            std::string::npos);
}

TEST(Vocabulary, L1Score) {
  const BowVector a{{1, 0.5}, {2, 0.5}}, b{{3, 1.0}}, c{{1, 0.25}, {3, 0.75}},
      d{{0, 0.1}, {2, 0.2}, {7, 0.7}};
  EXPECT_DOUBLE_EQ(Vocabulary::score(a, a), 1.0);
  EXPECT_DOUBLE_EQ(Vocabulary::score(a, b), 0.0);
  EXPECT_DOUBLE_EQ(Vocabulary::score(a, c), 0.25);
  EXPECT_DOUBLE_EQ(Vocabulary::score(c, a), 0.25);
  EXPECT_DOUBLE_EQ(Vocabulary::score(b, c), 0.75);
  EXPECT_DOUBLE_EQ(Vocabulary::score(a, d), 0.2);
  EXPECT_DOUBLE_EQ(Vocabulary::score(d, a), 0.2);
  EXPECT_EQ(Vocabulary::score(a, BowVector{}), 0.0);
  EXPECT_EQ(Vocabulary::score(BowVector{}, BowVector{}), 0.0);
  // 1 - 0.5 * sum |a_i - b_i| over the union of words.
  EXPECT_NEAR(Vocabulary::score(c, d), 1.0 - 0.5 * (0.1 + 0.25 + 0.2 + 0.75 + 0.7), 1e-15);

  BowVector x, y;
  small().transform(random_descriptors(300, 7), x);
  small().transform(random_descriptors(300, 8), y);
  EXPECT_NEAR(Vocabulary::score(x, x), 1.0, 1e-12);
  EXPECT_EQ(Vocabulary::score(x, y), Vocabulary::score(y, x));
  EXPECT_GT(Vocabulary::score(x, y), 0.0);
  EXPECT_LT(Vocabulary::score(x, y), 1.0);
}

TEST(Vocabulary, SamePlaceScoresHigher) {
  // Scenes the vocabulary was not trained on, each seen twice (300 features a view, the second
  // view rotated, scaled and shifted). Every scene must score well above any pairing of views of
  // different scenes; on these scenes the ratio is 2.2 to 3.0.
  const Vocabulary& v = trained();
  constexpr int kScenes = 5;
  std::vector<BowVector> first(kScenes), second(kScenes);
  for (int i = 0; i < kScenes; ++i) {
    const cv::Mat img = texture(static_cast<std::uint64_t>(i + 1));
    v.transform(orb_descriptors(img, 300), first[i]);
    v.transform(orb_descriptors(other_view(img), 300), second[i]);
  }
  for (int i = 0; i < kScenes; ++i) {
    const double same = Vocabulary::score(first[i], second[i]);
    double best_other = 0.0;
    for (int j = 0; j < kScenes; ++j) {
      if (j == i) continue;
      best_other = std::max({best_other, Vocabulary::score(first[i], second[j]),
                             Vocabulary::score(first[i], first[j]), Vocabulary::score(second[i], second[j])});
    }
    EXPECT_GT(same, 1.5 * best_other)
        << "scene " << i << ": same place " << same << ", best other " << best_other;
  }
}
