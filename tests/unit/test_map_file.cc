// Map files (docs/map-files.md): save -> load -> save gives the same bytes, the loaded map equals
// the saved one, frames relocalize in a loaded map and are tracked in its frame, localization only
// adds nothing, and every bad file stops with one line naming it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "error_of.h"
#include "lrd/map/map_file.h"
#include "lrd/system.h"
#include "lrd/util/binary_io.h"
#include "rendered_sequence.h"
#include "temp_dir.h"

namespace {

namespace fs = std::filesystem;
using lrd::test::config_for;
using lrd::test::error_of;
using lrd::test::static_sequence;
using lrd::test::TempDir;

std::string bytes_of(const fs::path& file) {
  return lrd::util::read_file_bytes(file, "test");
}

void write_bytes(const fs::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
}

// The static sequence's map, deterministic, saved once per test process.
const fs::path& saved_map() {
  static TempDir dir("map_file");
  static const fs::path file = [] {
    lrd::SystemOptions options;
    options.deterministic = true;
    lrd::System slam(config_for(static_sequence().camera), options);
    for (const auto& f : static_sequence().frames) slam.track_rgbd(f.rgb, f.depth, f.timestamp);
    slam.shutdown();
    const fs::path out = dir.path() / "static.lrdmap";
    slam.save_map(out);
    return out;
  }();
  return file;
}

lrd::SystemOptions options_with(bool localization_only) {
  lrd::SystemOptions o;
  o.deterministic = true;
  o.localization_only = localization_only;
  return o;
}

TEST(MapFile, SaveLoadSaveGivesIdenticalBytesAndTheSameMap) {
  const TempDir dir("map_file_rt");
  lrd::System loaded(config_for(static_sequence().camera), options_with(false));
  loaded.load_map(saved_map());
  loaded.save_map(dir.path() / "again.lrdmap");
  EXPECT_EQ(bytes_of(saved_map()), bytes_of(dir.path() / "again.lrdmap"));

  // The same keyframe poses and points, bit for bit, as a map loaded by itself.
  lrd::map::Map a;
  const lrd::map::MapFileHeader header = lrd::map::load_map_file(saved_map(), a);
  EXPECT_EQ(header.camera.fx, static_sequence().camera.fx);
  const lrd::events::MapSnapshot b = loaded.map_snapshot();
  ASSERT_GT(a.keyframe_count(), 2u);
  ASSERT_EQ(b.keyframes.size(), a.keyframe_count());
  ASSERT_EQ(b.points.size(), a.map_point_count());
  for (const auto& kf : b.keyframes) {
    const lrd::map::KeyFrame* k = a.keyframe(kf.keyframe_id);
    ASSERT_NE(k, nullptr);
    EXPECT_TRUE((k->T_wc().matrix().array() == kf.T_wc.matrix().array()).all()) << kf.keyframe_id;
  }
  const std::vector<lrd::map::MapPoint*> points = a.map_points();
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(points[i]->id(), b.points[i].id);
    EXPECT_EQ(points[i]->position(), b.points[i].position);
    EXPECT_EQ(points[i]->observations().size(), b.points[i].keyframes.size());
  }
  EXPECT_EQ(loaded.map_stats().loaded_keyframes, a.keyframe_count());
}

TEST(MapFile, FramesRelocalizeInALoadedMapAndAreTrackedInItsFrame) {
  const auto& seq = static_sequence();
  lrd::System slam(config_for(seq.camera), options_with(false));
  slam.load_map(saved_map());
  // A covered lens first: no place to recognise, the frame is not localized (not lost, no new map).
  const cv::Mat black(seq.frames[0].rgb.size(), CV_8UC3, cv::Scalar::all(0));
  const cv::Mat no_depth(seq.frames[0].depth.size(), seq.frames[0].depth.type(), cv::Scalar::all(0));
  EXPECT_EQ(slam.track_rgbd(black, no_depth, seq.frames[0].timestamp - 1.0).state,
            lrd::TrackingState::NotLocalized);
  // The sequence again from its middle: relocalized at once, in the saved map's frame (the first
  // camera of the run that made it), within a centimetre of the truth without any alignment.
  const Eigen::Isometry3d world_from_map = seq.ground_truth.front().pose;
  for (std::size_t i = 20; i < seq.frames.size(); ++i) {
    const auto& f = seq.frames[i];
    const lrd::TrackResult r = slam.track_rgbd(f.rgb, f.depth, f.timestamp);
    ASSERT_EQ(r.state, lrd::TrackingState::Ok) << "frame " << i;
    const Eigen::Isometry3d truth = world_from_map.inverse() * f.pose;
    EXPECT_LT((r.T_wc->translation() - truth.translation()).norm(), 0.01) << "frame " << i;
  }
  slam.shutdown();
  EXPECT_EQ(slam.map_stats().relocalizations, 1);
}

TEST(MapFile, LocalizationOnlyAddsNothingToTheMap) {
  const auto& seq = static_sequence();
  const std::string before = bytes_of(saved_map());
  lrd::System slam(config_for(seq.camera), options_with(true));
  slam.load_map(saved_map());
  const lrd::MapStats loaded = slam.map_stats();
  int tracked = 0;
  for (std::size_t i = 0; i < seq.frames.size(); i += 2)
    tracked += slam.track_rgbd(seq.frames[i].rgb, seq.frames[i].depth, seq.frames[i].timestamp).state ==
               lrd::TrackingState::Ok;
  slam.shutdown();
  EXPECT_GE(tracked, 20);
  EXPECT_EQ(slam.map_stats().keyframes, loaded.keyframes);
  EXPECT_EQ(slam.map_stats().map_points, loaded.map_points);
  EXPECT_EQ(bytes_of(saved_map()), before);

  // Localization only without a map is an error, not a one-keyframe map that never grows.
  lrd::System no_map(config_for(seq.camera), options_with(true));
  const auto& f = seq.frames[0];
  EXPECT_NE(error_of([&] {
              (void)no_map.track_rgbd(f.rgb, f.depth, f.timestamp);
            }).find("localization only needs a map to localize in"),
            std::string::npos);
}

TEST(MapFile, BadFilesStopWithOneLineNamingTheFile) {
  const TempDir dir("map_file_bad");
  const std::string good = bytes_of(saved_map());
  const auto load = [&](const std::string& name, const std::string& bytes) {
    const fs::path file = dir.path() / name;
    write_bytes(file, bytes);
    lrd::map::Map map;
    const std::string e = error_of([&] { (void)lrd::map::load_map_file(file, map); });
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_EQ(e.rfind(file.string() + ": ", 0), 0u) << e;
    return e;
  };
  EXPECT_NE(load("truncated.lrdmap", good.substr(0, good.size() / 2)).find("truncated"), std::string::npos);
  std::string flipped = good;
  flipped[good.size() / 2] = static_cast<char>(flipped[good.size() / 2] ^ 0x10);
  EXPECT_NE(load("corrupted.lrdmap", flipped).find("checksum"), std::string::npos);
  std::string version = good;
  version[8] = 9;
  EXPECT_NE(load("version.lrdmap", version).find("version 9"), std::string::npos);
  EXPECT_NE(load("magic.lrdmap", "not a map at all").find("not an lrd-slam map"), std::string::npos);
  EXPECT_NE(load("empty.lrdmap", "").find("not an lrd-slam map"), std::string::npos);
  lrd::map::Map map;
  EXPECT_NE(error_of([&] {
              (void)lrd::map::load_map_file(dir.path() / "missing.lrdmap", map);
            }).find("no such map"),
            std::string::npos);

  // Well-formed files (their checksums fit) whose objects disagree.
  const auto reload = [&](const std::string& name, const lrd::map::Map& edited) {
    return load(name, lrd::map::serialize_map(edited, lrd::map::MapFileHeader{}));
  };
  {
    lrd::map::Map m;
    (void)lrd::map::load_map_file(saved_map(), m);
    lrd::map::KeyFrame* kf = m.keyframes().back();
    std::size_t slot = 0;
    while (kf->map_point(slot) == nullptr) ++slot;
    kf->erase_map_point(slot);  // the point still observes the keyframe there
    EXPECT_NE(reload("slot.lrdmap", m).find("which holds another point there"), std::string::npos);
  }
  {
    lrd::map::Map m;
    (void)lrd::map::load_map_file(saved_map(), m);
    m.keyframes().back()->add_loop_edge(m.keyframes().front());  // one way only
    EXPECT_NE(reload("loop.lrdmap", m).find("that has none back"), std::string::npos);
  }
  {
    const lrd::map::Map empty;
    EXPECT_NE(reload("empty_map.lrdmap", empty).find("the map holds no keyframes"), std::string::npos);
  }

  // Another vocabulary or another camera: the system stays as it was.
  lrd::map::Map saved;
  const lrd::map::MapFileHeader header = lrd::map::load_map_file(saved_map(), saved);
  const std::string vocabulary = error_of([&] {
    lrd::map::check_map_matches(saved_map(), header, header.camera, header.vocabulary_fingerprint + 1);
  });
  EXPECT_NE(vocabulary.find("another vocabulary"), std::string::npos) << vocabulary;
  lrd::camera::PinholeCamera other = static_sequence().camera;
  other.fx += 1.0;
  lrd::System slam(config_for(other), options_with(false));
  const std::string camera = error_of([&] { slam.load_map(saved_map()); });
  EXPECT_NE(camera.find(saved_map().string() + ": the map's camera differs from this run's: fx"),
            std::string::npos)
      << camera;
  EXPECT_EQ(slam.map_stats().loaded_keyframes, 0u);
}

}  // namespace
