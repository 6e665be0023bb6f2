// The `dynamic` config section: modes, the geometry check's keys, their defaults and errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "error_of.h"
#include "lrd/config/config.h"
#include "lrd/dynamic/dynamic_params.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using lrd::dynamic::DynamicMode;
using lrd::dynamic::DynamicParams;
using lrd::test::error_of;

TEST(DynamicParams, ModesParseAndPrint) {
  for (DynamicMode m :
       {DynamicMode::Static, DynamicMode::Semantic, DynamicMode::Geometric, DynamicMode::Full})
    EXPECT_EQ(lrd::dynamic::parse_mode(lrd::dynamic::to_string(m)), m);
  EXPECT_EQ(lrd::dynamic::to_string(DynamicMode::Full), "full");
  EXPECT_EQ(lrd::dynamic::parse_mode("geometric"), DynamicMode::Geometric);
  for (const std::string bad : {"Full", "", "semantics", "dynamic"}) {
    const std::string msg = error_of([&] { (void)lrd::dynamic::parse_mode(bad); });
    EXPECT_NE(msg.find("'" + bad + "'"), std::string::npos) << msg;
    for (const char* choice : {"static", "semantic", "geometric", "full"})
      EXPECT_NE(msg.find(choice), std::string::npos) << msg;
  }
  EXPECT_FALSE(lrd::dynamic::uses_segmentation(DynamicMode::Static));
  EXPECT_FALSE(lrd::dynamic::uses_geometry(DynamicMode::Static));
  EXPECT_TRUE(lrd::dynamic::uses_segmentation(DynamicMode::Semantic));
  EXPECT_FALSE(lrd::dynamic::uses_geometry(DynamicMode::Semantic));
  EXPECT_FALSE(lrd::dynamic::uses_segmentation(DynamicMode::Geometric));
  EXPECT_TRUE(lrd::dynamic::uses_geometry(DynamicMode::Geometric));
  EXPECT_TRUE(lrd::dynamic::uses_segmentation(DynamicMode::Full));
  EXPECT_TRUE(lrd::dynamic::uses_geometry(DynamicMode::Full));
}

TEST(DynamicParams, FromConfig) {
  // Defaults from an empty section.
  const DynamicParams d = DynamicParams::from_config(lrd::config::NodeReader());
  EXPECT_EQ(d.mode, DynamicMode::Geometric);  // needs no model
  EXPECT_EQ(d.geometry.keyframes, 5);
  EXPECT_DOUBLE_EQ(d.geometry.max_parallax_deg, 30.0);
  EXPECT_DOUBLE_EQ(d.geometry.depth_threshold, 0.10);
  EXPECT_DOUBLE_EQ(d.geometry.depth_threshold_slope, 0.02);
  EXPECT_DOUBLE_EQ(d.geometry.max_depth, 6.0);
  EXPECT_EQ(d.geometry.neighbourhood, 2);
  EXPECT_DOUBLE_EQ(d.geometry.neighbourhood_agreement, 0.7);
  EXPECT_EQ(d.geometry.min_seeds, 3);
  EXPECT_DOUBLE_EQ(d.geometry.grow_band, 0.35);
  EXPECT_DOUBLE_EQ(d.geometry.min_keyframe_age_s, 0.2);
  EXPECT_EQ(d.geometry.known_surface_px, 8);

  lrd::test::TempDir tmp("dynamic_config");
  auto read = [&](const std::string& text) {
    const fs::path file = tmp.write("config.yaml", text);
    return DynamicParams::from_config(lrd::config::load_config(file).dynamic);
  };
  const DynamicParams p = read(
      "dynamic:\n  mode: full\n  geometry:\n    keyframes: 3\n    max_parallax_deg: 20\n"
      "    depth_threshold: 0.2\n    neighbourhood: 1\n    min_seeds: 5\n    grow_extent: 0.5\n"
      "    min_keyframe_age_s: 0.5\n    known_surface_px: 0\n");
  EXPECT_EQ(p.mode, DynamicMode::Full);
  EXPECT_EQ(p.geometry.keyframes, 3);
  EXPECT_DOUBLE_EQ(p.geometry.max_parallax_deg, 20.0);
  EXPECT_DOUBLE_EQ(p.geometry.depth_threshold, 0.2);
  EXPECT_EQ(p.geometry.neighbourhood, 1);
  EXPECT_EQ(p.geometry.min_seeds, 5);
  EXPECT_DOUBLE_EQ(p.geometry.grow_extent, 0.5);
  EXPECT_DOUBLE_EQ(p.geometry.min_keyframe_age_s, 0.5);
  EXPECT_EQ(p.geometry.known_surface_px, 0);
  EXPECT_DOUBLE_EQ(p.geometry.grow_step, 0.03);  // untouched: default

  std::string msg = error_of([&] { (void)read("dynamic:\n  mode: fulll\n"); });
  EXPECT_NE(msg.find("dynamic.mode"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fulll"), std::string::npos) << msg;
  EXPECT_NE(msg.find("config.yaml:2"), std::string::npos) << msg;
  msg = error_of([&] { (void)read("dynamic:\n  geometry:\n    keyframe: 3\n"); });
  EXPECT_NE(msg.find("dynamic.geometry.keyframe"), std::string::npos) << msg;
  msg = error_of([&] { (void)read("dynamic:\n  mod: full\n"); });
  EXPECT_NE(msg.find("dynamic.mod"), std::string::npos) << msg;
  msg = error_of([&] { (void)read("dynamic:\n  geometry:\n    keyframes: 0\n"); });
  EXPECT_NE(msg.find("dynamic.geometry.keyframes"), std::string::npos) << msg;
  msg = error_of([&] { (void)read("dynamic:\n  geometry:\n    neighbourhood_agreement: 1.5\n"); });
  EXPECT_NE(msg.find("dynamic.geometry.neighbourhood_agreement"), std::string::npos) << msg;
  msg = error_of([&] { (void)read("dynamic:\n  geometry:\n    depth_threshold: 0\n"); });
  EXPECT_NE(msg.find("dynamic.geometry.depth_threshold"), std::string::npos) << msg;
  msg = error_of([&] { (void)read("dynamic:\n  geometry:\n    known_surface_px: -1\n"); });
  EXPECT_NE(msg.find("dynamic.geometry.known_surface_px"), std::string::npos) << msg;
}
