// The occupancy stage (docs/occupancy.md): ray casting marks free space along each ray and a
// surface at its end, carving removes a person who walked on (not one who never moved), the floor
// and the 2-D grid, map_server files read back, bad settings as one-line errors, and the evaluator.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>

#include "error_of.h"
#include "lrd/config/config.h"
#include "lrd/eval/occupancy_accuracy.h"
#include "lrd/occupancy/floor_frame.h"
#include "lrd/occupancy/grid_2d.h"
#include "lrd/occupancy/occupancy_map.h"
#include "lrd/occupancy/occupancy_params.h"
#include "temp_dir.h"

namespace {

using lrd::occupancy::OccupancyMap;
using lrd::occupancy::OccupancyParams;
using lrd::occupancy::RayBundle;
using lrd::occupancy::VoxelState;

// Points on the plane z = depth (camera frame = map frame, camera at `origin`), x in [x0, x1],
// y in [y0, y1], every 1 cm; a box [bx0, bx1] x [by0, by1] in front at z = box_z replaces them
// where it covers them (a person), unless box_z <= 0.
RayBundle view(const Eigen::Vector3d& origin, double depth, double box_z = 0.0, double bx0 = -0.2,
               double bx1 = 0.2) {
  RayBundle r;
  r.origin = origin;
  for (double y = -0.6; y <= 0.6; y += 0.01)
    for (double x = -1.0; x <= 1.0; x += 0.01) {
      const bool on_box = box_z > 0.0 && x >= bx0 && x <= bx1;
      const double z = on_box ? box_z : depth;
      r.points.emplace_back(static_cast<float>(origin.x() + x * z / depth),
                            static_cast<float>(origin.y() + y), static_cast<float>(origin.z() + z));
      r.depth.push_back(static_cast<float>(z));
      r.hit.push_back(1);
    }
  return r;
}

// Every hit counts at once (plain OctoMap): the ray casting itself, one view at a time.
OccupancyParams plain() {
  OccupancyParams p;
  p.min_hit_keyframes = 1;
  return p;
}

}  // namespace

TEST(OccupancyMap, RaysAreFreeAlongTheWayAndOccupiedAtTheirEnd) {
  OccupancyMap map(plain());
  map.integrate(view(Eigen::Vector3d::Zero(), 2.0));
  EXPECT_EQ(map.state_at({0.0, 0.0, 0.5}), VoxelState::Free);
  EXPECT_EQ(map.state_at({0.3, -0.2, 1.5}), VoxelState::Free);
  EXPECT_EQ(map.state_at({0.0, 0.0, 2.01}), VoxelState::Occupied);
  EXPECT_EQ(map.state_at({0.5, 0.4, 2.01}), VoxelState::Occupied);
  EXPECT_EQ(map.state_at({0.0, 0.0, 2.6}), VoxelState::Unknown);  // behind the wall
  EXPECT_EQ(map.state_at({0.0, 1.5, 1.0}), VoxelState::Unknown);  // outside the view
  // The wall is one voxel thick: 2 m x 1.2 m at 5 cm is about 40 x 24 voxels.
  EXPECT_NEAR(static_cast<double>(map.occupied_count()), 41.0 * 25.0, 60.0);
}

TEST(OccupancyMap, AFarHitAddsLessEvidenceThanANearOne) {
  const OccupancyParams p;
  EXPECT_NEAR(OccupancyMap::hit_log_odds(p, 0.1), std::log(0.7 / 0.3), 1e-4);
  EXPECT_GT(OccupancyMap::hit_log_odds(p, 1.0), OccupancyMap::hit_log_odds(p, 3.0));
  EXPECT_GT(OccupancyMap::hit_log_odds(p, 6.0), 0.0f);
}

TEST(OccupancyMap, RaysBeyondTheRangeOnlyCarve) {
  OccupancyParams p;
  p.max_range = 1.5;
  OccupancyMap map(p);
  map.integrate(view(Eigen::Vector3d::Zero(), 2.0));
  EXPECT_EQ(map.state_at({0.0, 0.0, 1.2}), VoxelState::Free);
  EXPECT_EQ(map.state_at({0.0, 0.0, 2.01}), VoxelState::Unknown);
  EXPECT_EQ(map.occupied_count(), 0u);
}

TEST(OccupancyMap, APersonWhoWalkedAcrossTheCorridorIsCarvedOut) {
  // A person (a slab 40 cm wide at 1.5 m) in the first view, gone in the next ones from nearby
  // viewpoints: their rays to the wall pass where the person stood.
  OccupancyMap map(plain());
  map.integrate(view(Eigen::Vector3d::Zero(), 3.0, 1.5));
  EXPECT_EQ(map.state_at({0.0, 0.0, 1.51}), VoxelState::Occupied);
  for (int k = 1; k <= 4; ++k) map.integrate(view(Eigen::Vector3d(0.02 * k, 0.0, 0.0), 3.0));
  EXPECT_EQ(map.state_at({0.0, 0.0, 1.51}), VoxelState::Free);
  EXPECT_EQ(map.state_at({0.07, 0.12, 1.51}), VoxelState::Free);
  EXPECT_EQ(map.state_at({0.0, 0.0, 3.01}), VoxelState::Occupied);  // the wall behind stays
}

TEST(OccupancyMap, APersonStandingStillAllAlongStaysOccupied) {
  // What carving cannot know: nothing ever saw through them (docs/occupancy.md).
  OccupancyMap map(OccupancyParams{});
  for (int k = 0; k < 5; ++k) map.integrate(view(Eigen::Vector3d(0.02 * k, 0.0, 0.0), 3.0, 1.5));
  EXPECT_EQ(map.state_at({0.0, 0.0, 1.51}), VoxelState::Occupied);
  EXPECT_EQ(map.state_at({0.0, 0.0, 3.01}), VoxelState::Unknown);  // hidden behind them
}

// The bundle's points nearer than `z` (a slab in front of the wall: a part of a walker the mask
// missed) as the dense stage gives them: after the trusted ones, as measured next to the mask.
RayBundle slab_near_the_mask(RayBundle r, double timestamp, float z = 2.0f) {
  RayBundle out;
  out.timestamp = timestamp;
  out.origin = r.origin;
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) out.trusted = out.points.size();
    for (std::size_t i = 0; i < r.points.size(); ++i)
      if ((r.depth[i] < z) == (pass == 1)) {
        out.points.push_back(r.points[i]);
        out.depth.push_back(r.depth[i]);
        out.hit.push_back(r.hit[i]);
      }
  }
  out.measured = out.points.size();
  return out;
}

TEST(OccupancyMap, APartOfAWalkerTheMaskMissedInOneKeyframeIsNoObstacle) {
  // The default map: a voxel hit next to the mask is a surface once two keyframes at least 1 s
  // apart measured it. The missed part (a slab at 1.5 m, x in [-0.1, 0.1]) is elsewhere a second
  // later (the person walked on: x in [0.17, 0.37]); the wall, away from the mask, is a surface at
  // once.
  const auto slab_at = [](double x0, double x1, double t) {
    return slab_near_the_mask(view(Eigen::Vector3d(0.02 * t, 0.0, 0.0), 3.0, 1.5, x0, x1), t);
  };
  OccupancyMap map(OccupancyParams{});
  map.integrate(slab_at(-0.2, 0.2, 0.0));
  EXPECT_NE(map.state_at({0.0, 0.0, 1.51}), VoxelState::Occupied);
  EXPECT_EQ(map.state_at({-0.6, 0.0, 3.01}), VoxelState::Occupied);
  map.integrate(slab_at(0.3, 0.7, 1.0));
  EXPECT_NE(map.state_at({0.0, 0.0, 1.51}), VoxelState::Occupied);
  EXPECT_NE(map.state_at({0.27, 0.0, 1.51}), VoxelState::Occupied);
  EXPECT_EQ(map.state_at({0.9, 0.2, 3.01}), VoxelState::Occupied);
  // A keyframe a moment later (a person filling the view adds keyframes fast) sees the slab where
  // it was: not a second, independent measurement.
  map.integrate(slab_at(0.3, 0.7, 1.1));
  EXPECT_NE(map.state_at({0.27, 0.0, 1.51}), VoxelState::Occupied);
  // Measured again a second later, the slab is a surface (what stands still).
  map.integrate(slab_at(0.3, 0.7, 2.0));
  EXPECT_EQ(map.state_at({0.27, 0.0, 1.51}), VoxelState::Occupied);
  // Plain OctoMap keeps the first slab: one miss from the second view does not outweigh a hit.
  OccupancyMap every_hit(plain());
  every_hit.integrate(slab_at(-0.2, 0.2, 0.0));
  every_hit.integrate(slab_at(0.3, 0.7, 1.0));
  EXPECT_EQ(every_hit.state_at({0.0, 0.0, 1.51}), VoxelState::Occupied);
}

TEST(OccupancyMap, AMissedPartCopiedByTheRepairIntoLaterKeyframesDoesNotConfirmItself) {
  // The first keyframe measured a slab at 1.5 m next to its mask (a part of a walker the mask
  // missed); the repair copies it into the next keyframes' filled-in background, at the same
  // place in the world.
  const RayBundle first = slab_near_the_mask(view(Eigen::Vector3d::Zero(), 3.0, 1.5), 0.0);
  const auto later = [&](const Eigen::Vector3d& origin, bool copies_measured) {
    RayBundle r = view(origin, 3.0);
    r.timestamp = 50.0 * origin.x();  // 1 s apart
    r.trusted = r.points.size();
    for (std::size_t i = first.trusted; i < first.points.size(); ++i) {
      r.points.push_back(first.points[i]);
      r.depth.push_back(static_cast<float>(first.points[i].z() - origin.z()));
      r.hit.push_back(1);
    }
    r.measured = copies_measured ? r.points.size() : r.trusted;
    return r;
  };
  OccupancyMap repaired(OccupancyParams{});
  repaired.integrate(first);
  for (int k = 1; k <= 2; ++k) repaired.integrate(later(Eigen::Vector3d(0.02 * k, 0.0, 0.0), false));
  EXPECT_NE(repaired.state_at({0.0, 0.0, 1.51}), VoxelState::Occupied);
  EXPECT_EQ(repaired.state_at({0.6, 0.0, 3.01}), VoxelState::Occupied);
  // Had the later keyframes measured it themselves, it would be a surface.
  OccupancyMap measured(OccupancyParams{});
  measured.integrate(first);
  for (int k = 1; k <= 2; ++k) measured.integrate(later(Eigen::Vector3d(0.02 * k, 0.0, 0.0), true));
  EXPECT_EQ(measured.state_at({0.0, 0.0, 1.51}), VoxelState::Occupied);
}

TEST(OccupancyMap, PointsSeenThroughCarveTheirVoxelInsteadOfMarkingIt) {
  RayBundle r = view(Eigen::Vector3d::Zero(), 2.0);
  for (char& h : r.hit) h = 0;
  OccupancyMap map(OccupancyParams{});
  map.integrate(r);
  EXPECT_EQ(map.state_at({0.0, 0.0, 2.01}), VoxelState::Free);
  EXPECT_EQ(map.occupied_count(), 0u);
}

TEST(OccupancyMap, TheBinaryFileReadsBackTheSameMap) {
  lrd::test::TempDir dir("occupancy_bt");
  OccupancyMap map(plain());
  map.integrate(view(Eigen::Vector3d::Zero(), 2.0, 1.0));
  map.write_binary(dir.path() / "occupancy.bt");
  const OccupancyMap back = OccupancyMap::read_binary(dir.path() / "occupancy.bt", OccupancyParams{});
  EXPECT_DOUBLE_EQ(back.resolution(), 0.05);
  EXPECT_EQ(back.occupied_count(), map.occupied_count());
  EXPECT_EQ(back.free_count(), map.free_count());
  for (const Eigen::Vector3d& v : map.occupied_voxels()) EXPECT_EQ(back.state_at(v), VoxelState::Occupied);

  const auto bad =
      dir.write("bad.bt", "# Octomap OcTree binary file\nid OcTree\nsize 12\nres 0.05\ndata\nxx");
  const std::string e1 = lrd::test::error_of([&] { (void)OccupancyMap::read_binary(bad, {}); });
  EXPECT_NE(e1.find("bad.bt"), std::string::npos) << e1;
  EXPECT_NE(e1.find("corrupt"), std::string::npos) << e1;
  const auto other = dir.write("other.bt", "ply\nformat binary_little_endian 1.0\n");
  const std::string e2 = lrd::test::error_of([&] { (void)OccupancyMap::read_binary(other, {}); });
  EXPECT_NE(e2.find("not an OctoMap binary file"), std::string::npos) << e2;
}

namespace {
// A room seen from a camera 1.4 m above the floor, tilted 15 deg down (map frame = camera frame:
// y down, z forward): the floor, and a 0.5 m box standing on it 2 m ahead.
OccupancyMap room(double tilt_deg, Eigen::Matrix3d& world_to_map, std::vector<Eigen::Vector3d>& surface) {
  const Eigen::AngleAxisd tilt(tilt_deg * M_PI / 180.0, Eigen::Vector3d::UnitX());
  // World: x right, y forward, z up; camera at (0, 0, 1.4).
  Eigen::Matrix3d cam_from_world;
  cam_from_world << 1, 0, 0, 0, 0, -1, 0, 1, 0;  // camera y = -world z, camera z = world y
  world_to_map = tilt.toRotationMatrix() * cam_from_world;
  const Eigen::Vector3d eye(0, 0, 1.4);
  RayBundle r;
  const auto add = [&](const Eigen::Vector3d& world) {
    const Eigen::Vector3d m = world_to_map * (world - eye);
    r.points.push_back(m.cast<float>());
    surface.push_back(m);
    r.depth.push_back(static_cast<float>(std::max(0.1, m.z())));
    r.hit.push_back(1);
  };
  for (double x = -1.5; x <= 1.5; x += 0.02)
    for (double y = 0.8; y <= 3.0; y += 0.02)
      if (!(std::abs(x) <= 0.25 && y >= 1.75 && y <= 2.25)) add({x, y, 0.0});
  for (double x = -0.25; x <= 0.25; x += 0.02)
    for (double y = 1.75; y <= 2.25; y += 0.02) add({x, y, 0.5});
  for (double x = -0.25; x <= 0.25; x += 0.02)
    for (double z = 0.0; z <= 0.5; z += 0.02) add({x, 1.75, z});
  OccupancyParams p = plain();
  p.max_range = 4.0;
  OccupancyMap map(p);
  map.integrate(r);
  return map;
}
}  // namespace

TEST(OccupancyGrid, TheFloorIsFoundAndTheBoxIsAnObstacle) {
  Eigen::Matrix3d world_to_map;
  std::vector<Eigen::Vector3d> surface;
  const OccupancyMap map = room(15.0, world_to_map, surface);
  const lrd::occupancy::FloorFrame floor =
      lrd::occupancy::estimate_floor(surface, {0.0, -1.0, 0.0}, std::nullopt);
  const Eigen::Vector3d true_up = world_to_map * Eigen::Vector3d::UnitZ();
  EXPECT_GT(floor.up().dot(true_up), std::cos(1.0 * M_PI / 180.0)) << floor.up().transpose();
  EXPECT_NEAR(floor.height, -1.4, 0.02);  // 1.4 m below the camera, along up
  const lrd::occupancy::Grid2d grid = lrd::occupancy::project_to_grid(map, floor, 0.1, 1.8);
  ASSERT_GT(grid.width, 0);
  // The box's footprint (2 m ahead, at the camera's x) is occupied, the floor before it free.
  const auto state_under = [&](const Eigen::Vector3d& world) {
    const Eigen::Vector3d q = floor.to_floor(world_to_map * (world - Eigen::Vector3d(0, 0, 1.4)));
    int x = 0, y = 0;
    EXPECT_TRUE(grid.cell_of(q.head<2>(), x, y)) << world.transpose();
    return grid.at(x, y);
  };
  EXPECT_EQ(state_under({0.0, 2.0, 0.3}), lrd::occupancy::kOccupied);
  EXPECT_EQ(state_under({0.0, 1.2, 0.3}), lrd::occupancy::kFree);
  EXPECT_EQ(state_under({1.0, 2.0, 0.3}), lrd::occupancy::kFree);
  // A lone occupied voxel in the band (a speck) stays out of the grid unless asked for.
  OccupancyMap specked = room(15.0, world_to_map, surface);
  RayBundle speck;
  const Eigen::Vector3d speck_world(1.0, 1.2, 0.5);
  speck.origin = world_to_map * Eigen::Vector3d(1.0, 1.2, 1.0) - world_to_map * Eigen::Vector3d(0, 0, 1.4);
  speck.points.push_back((world_to_map * (speck_world - Eigen::Vector3d(0, 0, 1.4))).cast<float>());
  speck.depth.push_back(0.5f);
  speck.hit.push_back(1);
  for (int k = 0; k < 3; ++k) specked.integrate(speck);
  using lrd::occupancy::project_to_grid;
  const lrd::occupancy::Grid2d plain = project_to_grid(map, floor, 0.1, 1.8, false);
  const lrd::occupancy::Grid2d speckled = project_to_grid(specked, floor, 0.1, 1.8, false);
  ASSERT_EQ(speckled.cells.size(), plain.cells.size());
  EXPECT_EQ(speckled.count(lrd::occupancy::kOccupied), plain.count(lrd::occupancy::kOccupied) + 1);
  EXPECT_EQ(project_to_grid(specked, floor, 0.1, 1.8).count(lrd::occupancy::kOccupied),
            project_to_grid(map, floor, 0.1, 1.8).count(lrd::occupancy::kOccupied));
  // A fixed floor height takes the configured up as it is.
  const auto fixed = lrd::occupancy::estimate_floor(surface, {0.0, -1.0, 0.0}, -1.2);
  EXPECT_DOUBLE_EQ(fixed.height, -1.2);
  EXPECT_TRUE(fixed.up().isApprox(Eigen::Vector3d(0.0, -1.0, 0.0)));
}

TEST(OccupancyGrid, TheMapServerYamlAndImageReadBack) {
  lrd::test::TempDir dir("occupancy_grid");
  Eigen::Matrix3d world_to_map;
  std::vector<Eigen::Vector3d> surface;
  const OccupancyMap map = room(10.0, world_to_map, surface);
  const auto floor = lrd::occupancy::estimate_floor(surface, {0.0, -1.0, 0.0}, std::nullopt);
  const lrd::occupancy::Grid2d grid = lrd::occupancy::project_to_grid(map, floor, 0.1, 1.8);
  lrd::occupancy::write_map_server(grid, dir.path(), "occupancy_2d", {0.65, 0.196});
  const YAML::Node yaml = YAML::LoadFile((dir.path() / "occupancy_2d.yaml").string());
  EXPECT_EQ(yaml["image"].as<std::string>(), "occupancy_2d.pgm");
  EXPECT_DOUBLE_EQ(yaml["resolution"].as<double>(), 0.05);
  EXPECT_EQ(yaml["origin"].as<std::vector<double>>().size(), 3u);
  EXPECT_EQ(yaml["negate"].as<int>(), 0);
  EXPECT_DOUBLE_EQ(yaml["occupied_thresh"].as<double>(), 0.65);
  EXPECT_DOUBLE_EQ(yaml["free_thresh"].as<double>(), 0.196);

  const lrd::occupancy::Grid2d back = lrd::occupancy::read_map_server(dir.path() / "occupancy_2d.yaml");
  EXPECT_EQ(back.width, grid.width);
  EXPECT_EQ(back.height, grid.height);
  EXPECT_EQ(back.cells, grid.cells);
  EXPECT_NEAR(back.origin.x(), grid.origin.x(), 1e-6);
  EXPECT_NEAR(back.origin.y(), grid.origin.y(), 1e-6);
  EXPECT_TRUE(back.floor.rotation.isApprox(grid.floor.rotation, 1e-8));
  EXPECT_NEAR(back.floor.height, grid.floor.height, 1e-6);
  EXPECT_DOUBLE_EQ(back.max_height, 1.8);
  EXPECT_GT(back.count(lrd::occupancy::kOccupied), 50u);

  lrd::occupancy::write_grid_picture(grid, {Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 0.0, 1.0)},
                                     dir.path() / "occupancy_2d.png");
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "occupancy_2d.png"));

  const auto missing = dir.write("missing.yaml", "image: nowhere.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  const std::string e = lrd::test::error_of([&] { (void)lrd::occupancy::read_map_server(missing); });
  EXPECT_NE(e.find("missing.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("occupied_thresh"), std::string::npos) << e;
}

TEST(OccupancyParams, BadSettingsAreOneLineErrorsNamingTheKey) {
  lrd::test::TempDir dir("occupancy_params");
  const auto error_for = [&](const std::string& body) {
    const auto file = dir.write("c.yaml", "occupancy:\n" + body);
    return lrd::test::error_of(
        [&] { (void)OccupancyParams::from_config(lrd::config::load_config(file).occupancy); });
  };
  std::string e = error_for("  resolution: 0\n");
  EXPECT_NE(e.find("c.yaml:2"), std::string::npos) << e;
  EXPECT_NE(e.find("occupancy.resolution"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  e = error_for("  min_height: 1.0\n  max_height: 0.5\n");
  EXPECT_NE(e.find("occupancy.max_height"), std::string::npos) << e;
  EXPECT_NE(e.find("inverted"), std::string::npos) << e;
  e = error_for("  floor_height: low\n");
  EXPECT_NE(e.find("occupancy.floor_height"), std::string::npos) << e;
  e = error_for("  up: [0, 0]\n");
  EXPECT_NE(e.find("occupancy.up"), std::string::npos) << e;
  e = error_for("  min_hit_keyframes: 0\n");
  EXPECT_NE(e.find("occupancy.min_hit_keyframes"), std::string::npos) << e;
  e = error_for("  min_hit_interval: -1\n");
  EXPECT_NE(e.find("occupancy.min_hit_interval"), std::string::npos) << e;
  e = error_for("  resolutoin: 0.1\n");
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e;

  const auto ok = dir.write("ok.yaml", "occupancy:\n  floor_height: -1.2\n  up: [0, 0, 2]\n");
  const OccupancyParams p = OccupancyParams::from_config(lrd::config::load_config(ok).occupancy);
  ASSERT_TRUE(p.floor_height.has_value());
  EXPECT_DOUBLE_EQ(*p.floor_height, -1.2);
  EXPECT_TRUE(p.up.isApprox(Eigen::Vector3d::UnitZ()));
  const auto autofloor = dir.write("auto.yaml", "occupancy:\n  floor_height: auto\n");
  EXPECT_FALSE(OccupancyParams::from_config(lrd::config::load_config(autofloor).occupancy).floor_height);
}

TEST(OccupancyAccuracy, CountsMatchesGhostsAndThePeoplesPath) {
  // A wall at x = 2 from y = 0 to 1, z = 0 to 1.5 (samples every 1 cm); a person's points at
  // x = 1, y = 0.5, z = 0.2 to 1.6.
  std::vector<Eigen::Vector3f> scene, people;
  for (double y = 0.0; y <= 1.0; y += 0.01)
    for (double z = 0.0; z <= 1.5; z += 0.01) scene.emplace_back(2.0f, y, z);
  const std::vector<char> seen(scene.size(), 1);
  for (double z = 0.2; z <= 1.6; z += 0.05) people.emplace_back(1.0f, 0.5f, z);
  const lrd::eval::OccupancyTruth truth{scene, seen, people};
  // The map: the wall's voxels for y < 0.5 only (half recalled), one ghost voxel on the person.
  std::vector<Eigen::Vector3f> occupied;
  for (double y = 0.025; y < 0.5; y += 0.05)
    for (double z = 0.025; z < 1.5; z += 0.05) occupied.emplace_back(2.01f, y, z);
  occupied.emplace_back(1.0f, 0.5f, 1.0f);
  // The grid: cells along the wall occupied, the person's cell occupied (a ghost), others free.
  std::vector<Eigen::Vector3f> cells;
  std::vector<std::int8_t> states;
  for (double x = 0.025; x < 2.2; x += 0.05)
    for (double y = 0.025; y < 1.0; y += 0.05) {
      cells.emplace_back(x, y, 0.9f);
      const bool wall = std::abs(x - 2.0) < 0.03 && y < 0.5;
      const bool ghost = std::abs(x - 1.0) < 0.03 && std::abs(y - 0.5) < 0.03;
      states.push_back(wall || ghost ? 100 : 0);
    }
  const lrd::eval::OccupancyAccuracy a = lrd::eval::evaluate_occupancy(occupied, cells, states, truth, 0.05);
  EXPECT_EQ(a.occupied_voxels, occupied.size());
  EXPECT_EQ(a.matching_voxels, occupied.size() - 1);
  EXPECT_EQ(a.people_ghosts, 1u);
  EXPECT_NEAR(a.recall(), 0.5, 0.06);
  EXPECT_EQ(a.path_cells, 1u);  // the person never moved here: one cell, blocked by the ghost
  EXPECT_EQ(a.path_blocked_cells, 1u);
  ASSERT_EQ(a.blocked_path_cells.size(), 1u);  // named where it is, within half a cell
  EXPECT_NEAR(a.blocked_path_cells[0].x(), 1.0f, 0.026f);
  EXPECT_NEAR(a.blocked_path_cells[0].y(), 0.5f, 0.026f);
  EXPECT_NE(lrd::eval::describe(a).find("1 of 1 cells blocked at ("), std::string::npos);
  EXPECT_EQ(a.grid_occupied_cells, 24u);  // 2 x 10 along the wall, 4 around the person's point
  EXPECT_EQ(a.grid_matching_cells, 20u);
  EXPECT_NEAR(a.grid_recall(), 0.5, 0.1);
}

// A cell within two cells of a static obstacle is no path cell, judged from the cell's centre, not
// the person's point: a grid at 45 degrees to a wall puts the cell under a walker 11 cm from the
// wall 8 cm from it, where the wall's own voxels may fill it (walking_rpy counted it blocked).
TEST(OccupancyAccuracy, APathCellIsJudgedByItsOwnDistanceToObstacles) {
  std::vector<Eigen::Vector3f> scene, people;
  for (double x = 0.0; x <= 2.0; x += 0.01)
    for (double z = 0.0; z <= 1.5; z += 0.02) scene.emplace_back(x, 1.0f, z);  // the wall, y = 1
  const std::vector<char> seen(scene.size(), 1);
  for (double z = 0.2; z <= 1.6; z += 0.1) {
    people.emplace_back(1.0f, 0.89f, z);   // 11 cm from the wall
    people.emplace_back(1.0f, 0.778f, z);  // 22 cm from it
  }
  const lrd::eval::OccupancyTruth truth{scene, seen, people};
  // Cells on a 5 cm grid turned 45 degrees, one centred 8 cm from the wall (occupied by the wall's
  // spill), the rest free.
  const float a = 0.05f / std::sqrt(2.0f);
  std::vector<Eigen::Vector3f> cells;
  std::vector<std::int8_t> states;
  for (int i = -6; i <= 6; ++i)
    for (int j = -6; j <= 6; ++j) {
      const Eigen::Vector3f c(1.0f + (i - j) * a, 0.92f + (i + j) * a, 0.9f);
      if (c.y() > 1.0f) continue;
      cells.push_back(c);
      states.push_back(i == 0 && j == 0 ? 100 : 0);
    }
  const lrd::eval::OccupancyAccuracy acc = lrd::eval::evaluate_occupancy({}, cells, states, truth, 0.05);
  EXPECT_EQ(acc.path_cells, 1u);  // only the cell 22 cm from the wall
  EXPECT_EQ(acc.path_blocked_cells, 0u);
  EXPECT_EQ(acc.path_free_cells, 1u);
}
