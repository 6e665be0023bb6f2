// Autosave (autosave/autosaver.h): saves made while frames are tracked load and parse; a map
// captured and serialized in two steps is the map save_map writes; a save that cannot be written
// is counted and the run goes on; bad options are one line.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <thread>

#include "error_of.h"
#include "lrd/autosave/autosaver.h"
#include "lrd/io/trajectory.h"
#include "lrd/map/map_file.h"
#include "lrd/system.h"
#include "lrd/util/binary_io.h"
#include "rendered_sequence.h"
#include "temp_dir.h"

namespace {

namespace fs = std::filesystem;
using lrd::autosave::AutosaveOptions;
using lrd::autosave::Autosaver;
using lrd::test::config_for;
using lrd::test::error_of;
using lrd::test::static_sequence;
using lrd::test::TempDir;

// Tracks the static sequence with the autosaver subscribed; a frame every few milliseconds, so
// that saves every 10 ms fall between frames.
lrd::autosave::AutosaveStats track_with(lrd::System& slam, Autosaver& saver) {
  slam.subscribe(std::shared_ptr<Autosaver>(&saver, [](Autosaver*) {}));
  saver.start();
  for (const auto& f : static_sequence().frames) {
    slam.track_rgbd(f.rgb, f.depth, f.timestamp);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  saver.stop();
  return saver.stats();
}

TEST(Autosaver, SavesMadeWhileTrackingLoadAndParse) {
  const TempDir dir("autosave");
  lrd::System slam(config_for(static_sequence().camera));
  Autosaver saver(slam, AutosaveOptions{0.01, dir.path() / "map.lrdmap", dir.path() / "trajectory.txt"});
  const lrd::autosave::AutosaveStats stats = track_with(slam, saver);
  EXPECT_GE(stats.saves, 3u);
  EXPECT_EQ(stats.failures, 0u);
  ASSERT_EQ(stats.lock_seconds.size(), stats.saves);
  lrd::map::Map map;
  (void)lrd::map::load_map_file(dir.path() / "map.lrdmap", map);
  EXPECT_GE(map.keyframe_count(), 1u);
  EXPECT_GE(lrd::io::read_trajectory_tum(dir.path() / "trajectory.txt").size(), 1u);
  slam.shutdown();
}

TEST(Autosaver, TwoStepCaptureIsTheMapSaveMapWrites) {
  const TempDir dir("autosave_bytes");
  lrd::SystemOptions options;
  options.deterministic = true;
  lrd::System slam(config_for(static_sequence().camera), options);
  for (const auto& f : static_sequence().frames) slam.track_rgbd(f.rgb, f.depth, f.timestamp);
  slam.shutdown();
  slam.save_map(dir.path() / "map.lrdmap");
  std::string bytes;
  {
    const lrd::PendingMapSave pending = slam.capture_map();
    bytes = pending.serialize();
    EXPECT_GE(pending.lock_seconds(), 0.0);
  }
  EXPECT_EQ(bytes, lrd::util::read_file_bytes(dir.path() / "map.lrdmap", "test"));
}

TEST(Autosaver, ASaveThatCannotBeWrittenIsCountedAndTrackingGoesOn) {
  const TempDir dir("autosave_fail");
  lrd::System slam(config_for(static_sequence().camera));
  const fs::path missing = dir.path() / "no_such_folder";
  Autosaver saver(slam, AutosaveOptions{0.01, missing / "map.lrdmap", missing / "trajectory.txt"});
  const lrd::autosave::AutosaveStats stats = track_with(slam, saver);
  EXPECT_EQ(stats.saves, 0u);
  EXPECT_GE(stats.failures, 1u);
  EXPECT_EQ(slam.state(), lrd::TrackingState::Ok);
  EXPECT_FALSE(fs::exists(missing));
  slam.shutdown();
}

TEST(Autosaver, BadOptionsAreOneLine) {
  lrd::System slam(config_for(static_sequence().camera));
  EXPECT_NE(error_of([&] {
              Autosaver(slam, AutosaveOptions{0.0, "m", "t"});
            }).find("must be a positive number"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              Autosaver(slam, AutosaveOptions{1.0, "", "t"});
            }).find("needs a map file"),
            std::string::npos);
  slam.shutdown();
}

}  // namespace
