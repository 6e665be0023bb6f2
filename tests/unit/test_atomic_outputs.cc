// Every writer of a run's outputs on a full disk: one lrd::Error naming the file, the previous
// run's file with that name left as it was, no temporary beside it.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <opencv2/core.hpp>
#include <set>
#include <string>
#include <vector>

#include "file_size_limit.h"
#include "lrd/camera/pinhole_camera.h"
#include "lrd/dense/ply_io.h"
#include "lrd/io/image_file.h"
#include "lrd/io/trajectory.h"
#include "lrd/occupancy/grid_2d.h"
#include "lrd/occupancy/occupancy_map.h"
#include "lrd/rosbag2/mcap_writer.h"
#include "lrd/rosbag2/messages.h"
#include "lrd/rosbag2/sqlite_bag.h"
#include "lrd/runner/sequence_runner.h"
#include "lrd/synth/sequence_writer.h"
#include "temp_dir.h"

namespace {

namespace fs = std::filesystem;
using lrd::test::error_with_file_size_limit;
using lrd::test::names_in;
using lrd::test::TempDir;

struct Writer {
  std::string name;  // the file's name, as a run names it
  std::function<void(const fs::path&)> write;
  std::string problem = "cannot write (File too large)";  // what the error says after "FILE: "
};

lrd::io::Trajectory some_poses() {
  lrd::io::Trajectory t;
  for (int i = 0; i < 10; ++i) {
    lrd::io::StampedPose p;
    p.timestamp = 1.0 + 0.1 * i;
    p.pose.translation() = Eigen::Vector3d(0.01 * i, 0.0, 0.5);
    t.push_back(p);
  }
  return t;
}

lrd::occupancy::Grid2d some_grid() {
  lrd::occupancy::Grid2d g;
  g.width = g.height = 20;
  g.cells.assign(400, lrd::occupancy::kFree);
  g.cells[42] = lrd::occupancy::kOccupied;
  return g;
}

std::vector<Writer> writers() {
  using lrd::rosbag2::msg::kImageType;
  return {
      {"CameraTrajectory.txt", [](const fs::path& f) { lrd::io::write_trajectory_tum(f, some_poses()); }},
      {"kitti.txt", [](const fs::path& f) { lrd::io::write_trajectory_kitti(f, some_poses()); }},
      {"track_times.txt",
       [](const fs::path& f) {
         lrd::runner::write_track_times(f, {{}, {}});
       }},
      {"summary.json",
       [](const fs::path& f) { lrd::runner::write_summary_json(f, lrd::runner::RunReport{}); }},
      {"dense_map.ply",
       [](const fs::path& f) {
         lrd::dense::PointCloud cloud;
         cloud.points.assign(50, Eigen::Vector3f(1.0f, 2.0f, 3.0f));
         cloud.colours.assign(50, cv::Vec3b(10, 20, 30));
         lrd::dense::write_ply(f, cloud);
       }},
      {"dense_map.png",
       [](const fs::path& f) { lrd::io::write_image_file(f, cv::Mat(40, 60, CV_8UC3, 77)); }},
      {"occupancy.bt",
       [](const fs::path& f) {
         lrd::occupancy::OccupancyMap(lrd::occupancy::OccupancyParams{}).write_binary(f);
       }},
      {"occupancy_2d.pgm",
       [](const fs::path& f) {
         lrd::occupancy::write_map_server(some_grid(), f.parent_path(), "occupancy_2d");
       }},
      {"occupancy_2d.png", [](const fs::path& f) { lrd::occupancy::write_grid_picture(some_grid(), {}, f); }},
      {"settings.yaml",
       [](const fs::path& f) { lrd::synth::write_orbslam_settings(f, lrd::camera::PinholeCamera{}); }},
      {"x.mcap",
       [](const fs::path& f) {
         lrd::rosbag2::McapWriter w(f);
         const auto channel = w.add_channel(w.add_schema(kImageType, "ros2msg", ""), "/image", "cdr");
         w.write(channel, 1000, std::vector<std::uint8_t>(5000, 7));
         w.close();
       }},
      // sqlite3 says in its own words what failed.
      {"x.db3",
       [](const fs::path& f) {
         lrd::rosbag2::Sqlite3Writer w(f);
         w.write(w.add_topic({"/image", kImageType, "cdr"}), 1000, std::vector<std::uint8_t>(50000, 7));
         w.close();
       },
       ""},
  };
}

TEST(AtomicOutputs, EachWriterOnAFullDiskLeavesThePreviousFileAndNamesIt) {
  for (const Writer& w : writers()) {
    SCOPED_TRACE(w.name);
    TempDir dir("outputs");
    const fs::path file = dir.write(w.name, "the previous run's good file\n");
    const std::string message = error_with_file_size_limit(40, [&] { w.write(file); });
    if (w.problem.empty())
      EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
    else
      EXPECT_EQ(message, file.string() + ": " + w.problem);
    EXPECT_EQ(TempDir::read(file), "the previous run's good file\n");
    EXPECT_EQ(names_in(dir.path()), std::set<std::string>{w.name});
  }
}

// The same writers with room: the file is there whole, nothing beside it.
TEST(AtomicOutputs, EachWriterWithRoomReplacesThePreviousFile) {
  for (const Writer& w : writers()) {
    SCOPED_TRACE(w.name);
    TempDir dir("outputs");
    const fs::path file = dir.write(w.name, "the previous run's good file\n");
    EXPECT_EQ(error_with_file_size_limit(1 << 20, [&] { w.write(file); }), "no error");
    EXPECT_NE(TempDir::read(file), "the previous run's good file\n");
    std::set<std::string> expected{w.name};
    if (w.name == "occupancy_2d.pgm") expected.insert("occupancy_2d.yaml");
    EXPECT_EQ(names_in(dir.path()), expected);
  }
}

}  // namespace
