// lrd::config::load_config and NodeReader: one section per module, unknown keys rejected.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "lrd/config/config.h"
#include "lrd/dense/dense_params.h"
#include "lrd/dynamic/dynamic_params.h"
#include "lrd/mapping/local_mapper.h"
#include "lrd/segmentation/segmentation_params.h"
#include "lrd/tracking/tracker.h"
#include "lrd/util/error.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using lrd::config::load_config;

namespace {

class ConfigTest : public ::testing::Test {
 protected:
  fs::path write(const std::string& name, const std::string& text) const { return tmp_.write(name, text); }

  // The message load_config(text) fails with.
  std::string error_of(const std::string& text) const {
    const fs::path p = write("bad.yaml", text);
    try {
      (void)load_config(p);
    } catch (const lrd::Error& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
      EXPECT_EQ(msg.rfind(p.string(), 0), 0u) << "message should start with the file: " << msg;
      return msg;
    }
    ADD_FAILURE() << "expected lrd::Error for:\n" << text;
    return {};
  }

  lrd::test::TempDir tmp_{"config"};
  const fs::path dir_ = tmp_.path();
};

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace

TEST_F(ConfigTest, ShippedDefaultConfigLoadsWithDefaults) {
  const auto cfg = load_config(fs::path(LRD_SOURCE_DIR) / "config" / "default.yaml");
  const auto tum3 = lrd::camera::camera_preset("tum3");
  EXPECT_EQ(cfg.camera.name, "tum3");
  EXPECT_DOUBLE_EQ(cfg.camera.fx, tum3.fx);
  const lrd::features::OrbParams orb;
  EXPECT_EQ(cfg.features.n_features, orb.n_features);
  EXPECT_FLOAT_EQ(cfg.features.scale_factor, orb.scale_factor);
  EXPECT_EQ(cfg.features.n_levels, orb.n_levels);
  EXPECT_EQ(cfg.features.ini_th_fast, orb.ini_th_fast);
  EXPECT_EQ(cfg.features.min_th_fast, orb.min_th_fast);
  EXPECT_EQ(cfg.output.dir, fs::path("output"));
  EXPECT_TRUE(cfg.output.save_trajectory);
  EXPECT_TRUE(cfg.output.save_keyframes);
}

TEST_F(ConfigTest, EmptyFileGivesDefaults) {
  const auto cfg = load_config(write("empty.yaml", "# nothing\n"));
  EXPECT_EQ(cfg.camera.name, "tum3");
  EXPECT_EQ(cfg.features.n_features, 1000);
}

TEST_F(ConfigTest, PresetCameraWithOverrides) {
  const auto cfg =
      load_config(write("c.yaml",
                        "camera:\n  preset: tum2\n  depth_map_factor: 5000\n  disparity_sigma: 0.5\n"
                        "features:\n  n_features: 1500\n  scale_factor: 1.5\n"
                        "output:\n  dir: runs/a\n  save_keyframes: true\n"));
  const auto tum2 = lrd::camera::camera_preset("tum2");
  EXPECT_EQ(cfg.camera.name, "tum2");
  EXPECT_DOUBLE_EQ(cfg.camera.fx, tum2.fx);
  EXPECT_DOUBLE_EQ(cfg.camera.distortion.k1, tum2.distortion.k1);
  EXPECT_DOUBLE_EQ(cfg.camera.depth_map_factor, 5000.0);  // overridden
  EXPECT_DOUBLE_EQ(cfg.camera.disparity_sigma, 0.5);
  EXPECT_EQ(cfg.features.n_features, 1500);
  EXPECT_FLOAT_EQ(cfg.features.scale_factor, 1.5f);
  EXPECT_EQ(cfg.features.n_levels, 8);
  EXPECT_EQ(cfg.output.dir, fs::path("runs/a"));
  EXPECT_TRUE(cfg.output.save_keyframes);
}

TEST_F(ConfigTest, ExplicitCamera) {
  const auto cfg = load_config(write("c.yaml",
                                     "camera:\n  fx: 500\n  fy: 501\n  cx: 320.5\n  cy: 240.5\n  k1: 0.1\n"
                                     "  width: 320\n  height: 240\n  rgb_order: false\n"));
  EXPECT_EQ(cfg.camera.name, "custom");
  EXPECT_DOUBLE_EQ(cfg.camera.fx, 500.0);
  EXPECT_DOUBLE_EQ(cfg.camera.fy, 501.0);
  EXPECT_DOUBLE_EQ(cfg.camera.cx, 320.5);
  EXPECT_DOUBLE_EQ(cfg.camera.cy, 240.5);
  EXPECT_DOUBLE_EQ(cfg.camera.distortion.k1, 0.1);
  EXPECT_EQ(cfg.camera.width, 320);
  EXPECT_FALSE(cfg.camera.rgb_order);
  const std::string msg = error_of("camera:\n  fx: 500\n  fy: 500\n  cx: 320\n");
  EXPECT_TRUE(contains(msg, "missing required key 'camera.cy'")) << msg;
}

TEST_F(ConfigTest, SettingsFileCameraRelativeToConfig) {
  fs::copy_file(fs::path(LRD_SOURCE_DIR) / "config" / "TUM1.yaml", dir_ / "TUM1.yaml");
  const auto cfg = load_config(write("c.yaml", "camera:\n  settings: TUM1.yaml\nfeatures:\n  n_levels: 4\n"));
  EXPECT_EQ(cfg.camera.name, "TUM1");
  EXPECT_DOUBLE_EQ(cfg.camera.fx, 517.306408);
  EXPECT_DOUBLE_EQ(cfg.camera.distortion.k3, 1.163314);
  EXPECT_EQ(cfg.features.n_features, 1000);
  EXPECT_EQ(cfg.features.n_levels, 4);

  const std::string msg = error_of("camera:\n  preset: tum1\n  settings: TUM1.yaml\n");
  EXPECT_TRUE(contains(msg, "camera.settings")) << msg;
}

TEST_F(ConfigTest, UnknownKeyNamedWithLineAndSuggestion) {
  const std::string msg = error_of("features:\n  n_features: 800\n  nfeaturs: 900\n");
  EXPECT_TRUE(contains(msg, "bad.yaml:3: unknown key 'features.nfeaturs'")) << msg;
  EXPECT_TRUE(contains(msg, "did you mean 'n_features'")) << msg;
  EXPECT_TRUE(contains(error_of("camera:\n  preset: tum1\n  fxx: 3\n"), "unknown key 'camera.fxx'"));
  EXPECT_TRUE(contains(error_of("output:\n  directory: x\n"), "unknown key 'output.directory'"));
}

TEST_F(ConfigTest, UnknownSectionNamed) {
  const std::string msg = error_of("features: {}\ntrackng:\n  a: 1\n");
  EXPECT_TRUE(contains(msg, "bad.yaml:2: unknown section 'trackng'")) << msg;
  EXPECT_TRUE(contains(msg, "did you mean 'tracking'")) << msg;
}

TEST_F(ConfigTest, WrongTypeNamesKeyAndLine) {
  std::string msg = error_of("features:\n  n_levels: 8\n  n_features: many\n");
  EXPECT_TRUE(contains(msg, "bad.yaml:3: key 'features.n_features' must be an integer, got 'many'")) << msg;
  msg = error_of("output:\n  save_keyframes: maybe\n");
  EXPECT_TRUE(contains(msg, "bad.yaml:2: key 'output.save_keyframes' must be a boolean")) << msg;
  msg = error_of("camera:\n  preset: [tum1]\n");
  EXPECT_TRUE(contains(msg, "bad.yaml:2: key 'camera.preset' must be a string, got a list")) << msg;
  msg = error_of("features: 5\n");
  EXPECT_TRUE(contains(msg, "bad.yaml:1: section 'features' must be a mapping")) << msg;
}

TEST_F(ConfigTest, OutOfRangeAndBadPreset) {
  std::string msg = error_of("features:\n  scale_factor: 0.9\n");
  EXPECT_TRUE(contains(msg, "bad.yaml:2: key 'features.scale_factor' must be > 1")) << msg;
  msg = error_of("camera:\n  preset: tum3\n  disparity_sigma: 0\n");
  EXPECT_TRUE(contains(msg, "bad.yaml:3: key 'camera.disparity_sigma' must be > 0")) << msg;
  // Tracking's keys are checked when the tracker reads its section.
  auto tracking_error = [&](const std::string& file, const std::string& text) {
    try {
      (void)lrd::tracking::TrackerParams::from_config(load_config(write(file, text)).tracking);
    } catch (const lrd::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  msg = tracking_error("t.yaml", "tracking:\n  keyframe_coverage: 1.5\n");
  EXPECT_TRUE(contains(msg, "t.yaml:2: key 'tracking.keyframe_coverage' must be in [0, 1]")) << msg;
  msg = tracking_error("c.yaml", "tracking:\n  keyframe_close_untracked: -1\n");
  EXPECT_TRUE(contains(msg, "c.yaml:2: key 'tracking.keyframe_close_untracked' must be >= 0")) << msg;
  const auto set = load_config(write("s.yaml", "tracking:\n  keyframe_close_tracked: 100\n"));
  EXPECT_EQ(lrd::tracking::TrackerParams::from_config(set.tracking).keyframe_close_tracked, 100);
  msg = error_of("camera:\n  preset: tum4\n");
  EXPECT_TRUE(contains(msg, "bad.yaml:2: key 'camera.preset'")) << msg;
  EXPECT_TRUE(contains(msg, "tum4")) << msg;
}

TEST_F(ConfigTest, SyntaxErrorsAndMissingFile) {
  std::string msg = error_of("features:\n  n_features: [1, 2\n");
  EXPECT_TRUE(contains(msg, "YAML syntax error")) << msg;
  msg = error_of("features:\n  n_features: 1\n  n_features: 2\n");
  EXPECT_TRUE(contains(msg, "bad.yaml:3: duplicate key 'features.n_features'")) << msg;
  msg = error_of("%YAML:1.0\nCamera.fx: 500\n");
  EXPECT_TRUE(contains(msg, "ORB-SLAM settings file")) << msg;
  try {
    (void)load_config(dir_ / "missing.yaml");
    FAIL() << "expected lrd::Error";
  } catch (const lrd::Error& e) {
    EXPECT_TRUE(contains(e.what(), "missing.yaml: config file not found")) << e.what();
  }
}

TEST_F(ConfigTest, LaterModuleSectionKeptForItsReader) {
  const auto cfg = load_config(write("c.yaml",
                                     "tracking:\n  min_inliers: 20\n  motion_model: true\n"
                                     "  window:\n    size: 5\n"
                                     "dense:\n  voxel_size: 0.01\n"));
  // What the tracking module will do with its section.
  lrd::config::NodeReader tracking = cfg.tracking;
  EXPECT_EQ(tracking.prefix(), "tracking");
  EXPECT_EQ(tracking.get("min_inliers", 15), 20);
  EXPECT_TRUE(tracking.get("motion_model", false));
  EXPECT_DOUBLE_EQ(tracking.get("max_dt", 0.5), 0.5);  // absent: default
  lrd::config::NodeReader window = tracking.section("window");
  EXPECT_EQ(window.get("size", 3), 5);
  EXPECT_NO_THROW(window.finish());
  EXPECT_NO_THROW(tracking.finish());

  lrd::config::NodeReader dense = cfg.dense;
  EXPECT_EQ(dense.get<std::string>("mode", "tsdf"), "tsdf");
  try {
    dense.finish();  // voxel_size was never read: unknown to this module
    FAIL() << "expected lrd::Error";
  } catch (const lrd::Error& e) {
    EXPECT_TRUE(contains(e.what(), "c.yaml:7: unknown key 'dense.voxel_size'")) << e.what();
  }
  try {
    lrd::config::NodeReader t2 = cfg.tracking;
    (void)t2.get("min_inliers", std::string("x"));
    (void)t2.get("motion_model", 1);
    FAIL() << "expected lrd::Error";
  } catch (const lrd::Error& e) {
    EXPECT_TRUE(contains(e.what(), "c.yaml:3: key 'tracking.motion_model' must be an integer, got 'true'"))
        << e.what();
  }
  // Absent sections are empty readers.
  lrd::config::NodeReader mapping = cfg.mapping;
  EXPECT_EQ(mapping.get("local_window", 10), 10);
  EXPECT_NO_THROW(mapping.finish());
}

// The shipped default.yaml documents the tracking and mapping keys with the code's defaults.
TEST_F(ConfigTest, ShippedDefaultTrackingAndMappingSectionsMatchCodeDefaults) {
  const auto cfg = load_config(fs::path(LRD_SOURCE_DIR) / "config" / "default.yaml");
  const auto t = lrd::tracking::TrackerParams::from_config(cfg.tracking);
  const lrd::tracking::TrackerParams td;
  EXPECT_EQ(t.init_min_features, td.init_min_features);
  EXPECT_FLOAT_EQ(t.motion_model_radius, td.motion_model_radius);
  EXPECT_EQ(t.min_local_map_inliers, td.min_local_map_inliers);
  EXPECT_EQ(t.max_local_keyframes, td.max_local_keyframes);
  EXPECT_DOUBLE_EQ(t.reference_ratio, td.reference_ratio);
  EXPECT_EQ(t.keyframe_close_points, td.keyframe_close_points);
  EXPECT_EQ(t.keyframe_close_tracked, td.keyframe_close_tracked);
  EXPECT_EQ(t.keyframe_close_untracked, td.keyframe_close_untracked);
  EXPECT_DOUBLE_EQ(t.keyframe_coverage, td.keyframe_coverage);
  const auto m = lrd::mapping::LocalMapperParams::from_config(cfg.mapping);
  const lrd::mapping::LocalMapperParams md;
  EXPECT_EQ(m.triangulation_neighbours, md.triangulation_neighbours);
  EXPECT_EQ(m.local_ba, md.local_ba);
  EXPECT_EQ(m.ba.first_iterations, md.ba.first_iterations);
  EXPECT_EQ(m.ba.second_iterations, md.ba.second_iterations);
  EXPECT_DOUBLE_EQ(m.culling.redundant_ratio, md.culling.redundant_ratio);
  EXPECT_DOUBLE_EQ(m.culling.place_redundant_ratio, md.culling.place_redundant_ratio);
  EXPECT_EQ(m.max_queued, md.max_queued);
}

TEST_F(ConfigTest, TrackingAndMappingKeysAreChecked) {
  const auto cfg = load_config(
      write("t.yaml", "tracking:\n  min_local_map_inlier: 40\nmapping:\n  redundant_ratio: 1.5\n"));
  try {
    (void)lrd::tracking::TrackerParams::from_config(cfg.tracking);
    FAIL() << "typo accepted";
  } catch (const lrd::Error& e) {
    EXPECT_TRUE(contains(e.what(), "t.yaml:2")) << e.what();
    EXPECT_TRUE(contains(e.what(), "min_local_map_inliers")) << e.what();
  }
  try {
    (void)lrd::mapping::LocalMapperParams::from_config(cfg.mapping);
    FAIL() << "out-of-range value accepted";
  } catch (const lrd::Error& e) {
    EXPECT_TRUE(contains(e.what(), "mapping.redundant_ratio")) << e.what();
  }
  const auto place =
      load_config(write("p.yaml", "mapping:\n  place_angle_deg: 5\n  place_keyframes_apart: 0\n"));
  try {
    (void)lrd::mapping::LocalMapperParams::from_config(place.mapping);
    FAIL() << "out-of-range value accepted";
  } catch (const lrd::Error& e) {
    EXPECT_TRUE(contains(e.what(), "mapping.place_keyframes_apart")) << e.what();
  }
}

// The shipped default.yaml documents the dynamic and segmentation keys with the code's defaults.
TEST_F(ConfigTest, ShippedDefaultDynamicAndSegmentationSectionsMatchCodeDefaults) {
  const auto cfg = load_config(fs::path(LRD_SOURCE_DIR) / "config" / "default.yaml");
  const auto d = lrd::dynamic::DynamicParams::from_config(cfg.dynamic);
  const lrd::dynamic::DynamicParams dd;
  EXPECT_EQ(d.mode, dd.mode);
  EXPECT_EQ(d.geometry.keyframes, dd.geometry.keyframes);
  EXPECT_DOUBLE_EQ(d.geometry.max_parallax_deg, dd.geometry.max_parallax_deg);
  EXPECT_DOUBLE_EQ(d.geometry.depth_threshold, dd.geometry.depth_threshold);
  EXPECT_DOUBLE_EQ(d.geometry.depth_threshold_slope, dd.geometry.depth_threshold_slope);
  EXPECT_DOUBLE_EQ(d.geometry.seed_support, dd.geometry.seed_support);
  EXPECT_EQ(d.geometry.region_dilation_px, dd.geometry.region_dilation_px);
  EXPECT_DOUBLE_EQ(d.geometry.grow_band, dd.geometry.grow_band);
  EXPECT_DOUBLE_EQ(d.geometry.min_keyframe_age_s, dd.geometry.min_keyframe_age_s);
  const auto s = lrd::segmentation::SegmentationParams::from_config(cfg.segmentation);
  const lrd::segmentation::SegmentationParams sd;
  EXPECT_EQ(s.backend, sd.backend);
  EXPECT_EQ(s.schedule, sd.schedule);
  EXPECT_DOUBLE_EQ(s.max_wait_ms, sd.max_wait_ms);
  EXPECT_EQ(s.dilation_px, sd.dilation_px);
  EXPECT_EQ(s.max_age_dilation_px, sd.max_age_dilation_px);
  EXPECT_EQ(s.onnx.input_width, sd.onnx.input_width);
  EXPECT_EQ(s.onnx.classes, lrd::segmentation::voc_classes());
  EXPECT_EQ(s.onnx.dynamic_classes, lrd::segmentation::voc_dynamic_classes());
  EXPECT_EQ(s.onnx.dynamic_ids, (std::vector<int>{15, 3, 8, 10, 12, 13, 17}));
  EXPECT_NEAR(s.onnx.scale, 1.0 / 255.0, 1e-15);
  EXPECT_TRUE(s.masks.dynamic_values.empty());
  const auto dn = lrd::dense::DenseParams::from_config(cfg.dense);
  const lrd::dense::DenseParams dn0;
  EXPECT_EQ(dn.enabled, dn0.enabled);
  EXPECT_DOUBLE_EQ(dn.voxel_size, dn0.voxel_size);
  EXPECT_DOUBLE_EQ(dn.max_depth, dn0.max_depth);
  EXPECT_EQ(dn.pixel_stride, dn0.pixel_stride);
  EXPECT_DOUBLE_EQ(dn.depth_edge, dn0.depth_edge);
  EXPECT_DOUBLE_EQ(dn.max_memory_mb, dn0.max_memory_mb);
  EXPECT_EQ(dn.repair.enabled, dn0.repair.enabled);
  EXPECT_EQ(dn.repair.keyframes, dn0.repair.keyframes);
  EXPECT_DOUBLE_EQ(dn.repair.max_depth, dn0.repair.max_depth);
  EXPECT_DOUBLE_EQ(dn.repair.depth_edge, dn0.repair.depth_edge);
  EXPECT_DOUBLE_EQ(dn.repair.surface_band, dn0.repair.surface_band);
  EXPECT_EQ(dn.repair.pixel_stride, dn0.repair.pixel_stride);
  EXPECT_EQ(dn.free_space.votes, dn0.free_space.votes);
  EXPECT_EQ(dn.free_space.keyframes, dn0.free_space.keyframes);
  EXPECT_EQ(dn.free_space.step, dn0.free_space.step);
  EXPECT_DOUBLE_EQ(dn.free_space.margin, dn0.free_space.margin);
  EXPECT_DOUBLE_EQ(dn.free_space.margin_ratio, dn0.free_space.margin_ratio);
}

TEST_F(ConfigTest, DenseKeysAreCheckedAndUnknownOnesRefused) {
  const auto cfg = load_config(write("dn.yaml", "dense:\n  voxel_size: 0\n"));
  try {
    (void)lrd::dense::DenseParams::from_config(cfg.dense);
    FAIL() << "voxel_size 0 accepted";
  } catch (const lrd::Error& e) {
    EXPECT_TRUE(contains(e.what(), "dn.yaml:2")) << e.what();
    EXPECT_TRUE(contains(e.what(), "dense.voxel_size")) << e.what();
  }
  const auto cap = load_config(write("dm.yaml", "dense:\n  max_memory_mb: -1\n"));
  try {
    (void)lrd::dense::DenseParams::from_config(cap.dense);
    FAIL() << "max_memory_mb -1 accepted";
  } catch (const lrd::Error& e) {
    EXPECT_TRUE(contains(e.what(), "dm.yaml:2")) << e.what();
    EXPECT_TRUE(contains(e.what(), "dense.max_memory_mb")) << e.what();
  }
  const auto typo = load_config(write("dt.yaml", "dense:\n  repair:\n    keyframe: 5\n"));
  try {
    (void)lrd::dense::DenseParams::from_config(typo.dense);
    FAIL() << "unknown key accepted";
  } catch (const lrd::Error& e) {
    EXPECT_TRUE(contains(e.what(), "dense.repair.keyframe")) << e.what();
  }
}

TEST_F(ConfigTest, DynamicModeTypoIsAnErrorNamingTheChoices) {
  const auto cfg = load_config(write("d.yaml", "dynamic:\n  mode: ful\n"));
  try {
    (void)lrd::dynamic::DynamicParams::from_config(cfg.dynamic);
    FAIL() << "typo accepted";
  } catch (const lrd::Error& e) {
    EXPECT_TRUE(contains(e.what(), "d.yaml:2")) << e.what();
    EXPECT_TRUE(contains(e.what(), "full")) << e.what();
  }
}
