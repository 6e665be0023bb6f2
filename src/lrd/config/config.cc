#include "lrd/config/config.h"

#include <fstream>
#include <optional>
#include <string>

#include "lrd/config/orbslam_settings.h"
#include "lrd/config/plausibility.h"
#include "lrd/util/error.h"

namespace lrd::config {
namespace {

camera::PinholeCamera read_camera(NodeReader& r, std::optional<features::OrbParams>& settings_orb) {
  const bool has_preset = r.has("preset");
  const bool has_settings = r.has("settings");
  if (has_preset && has_settings) r.check(false, "settings", "cannot be combined with 'camera.preset'");

  camera::PinholeCamera cam;
  if (has_preset) {
    const auto name = r.get<std::string>("preset", "");
    try {
      cam = camera::camera_preset(name);
    } catch (const Error& e) {
      r.check(false, "preset", std::string("is invalid: ") + e.what());
    }
  } else if (has_settings) {
    std::filesystem::path settings = r.get<std::filesystem::path>("settings", {});
    if (settings.is_relative()) settings = r.file().parent_path() / settings;
    const Settings s = read_orbslam_settings(settings);
    cam = s.camera;
    settings_orb = s.orb;
  } else {
    // Explicit calibration: the intrinsics cannot sensibly default.
    cam.fx = r.require<double>("fx");
    cam.fy = r.require<double>("fy");
    cam.cx = r.require<double>("cx");
    cam.cy = r.require<double>("cy");
  }
  // Any field may override the preset / settings file.
  cam.name = r.get("name", cam.name);
  cam.width = r.get("width", cam.width);
  cam.height = r.get("height", cam.height);
  cam.fx = r.get("fx", cam.fx);
  cam.fy = r.get("fy", cam.fy);
  cam.cx = r.get("cx", cam.cx);
  cam.cy = r.get("cy", cam.cy);
  cam.distortion.k1 = r.get("k1", cam.distortion.k1);
  cam.distortion.k2 = r.get("k2", cam.distortion.k2);
  cam.distortion.p1 = r.get("p1", cam.distortion.p1);
  cam.distortion.p2 = r.get("p2", cam.distortion.p2);
  cam.distortion.k3 = r.get("k3", cam.distortion.k3);
  cam.fps = r.get("fps", cam.fps);
  cam.bf = r.get("bf", cam.bf);
  cam.th_depth = r.get("th_depth", cam.th_depth);
  cam.depth_map_factor = r.get("depth_map_factor", cam.depth_map_factor);
  cam.rgb_order = r.get("rgb_order", cam.rgb_order);
  cam.disparity_sigma = r.get("disparity_sigma", cam.disparity_sigma);
  cam.readout_time = r.get("readout_time", cam.readout_time);
  r.check(cam.width > 0, "width", "must be > 0");
  r.check(cam.height > 0, "height", "must be > 0");
  r.check(cam.fx > 0.0, "fx", "must be > 0");
  r.check(cam.fy > 0.0, "fy", "must be > 0");
  r.check(cam.fps > 0.0, "fps", "must be > 0");
  r.check(cam.bf > 0.0, "bf", "must be > 0");
  r.check(cam.th_depth > 0.0, "th_depth", "must be > 0");
  r.check(cam.depth_map_factor > 0.0, "depth_map_factor", "must be > 0");
  r.check(cam.disparity_sigma > 0.0, "disparity_sigma", "must be > 0");
  if (const auto bad = implausible_camera(cam)) r.check(false, bad->field, bad->problem);
  r.finish();
  return cam;
}

features::OrbParams read_features(NodeReader& r, const features::OrbParams& base) {
  features::OrbParams orb = base;
  orb.n_features = r.get("n_features", orb.n_features);
  orb.scale_factor = r.get("scale_factor", orb.scale_factor);
  orb.n_levels = r.get("n_levels", orb.n_levels);
  orb.ini_th_fast = r.get("ini_th_fast", orb.ini_th_fast);
  orb.min_th_fast = r.get("min_th_fast", orb.min_th_fast);
  r.check(orb.n_features > 0, "n_features", "must be > 0");
  r.check(orb.scale_factor > 1.0f, "scale_factor", "must be > 1");
  r.check(orb.n_levels >= 1 && orb.n_levels <= 32, "n_levels", "must be in [1, 32]");
  r.check(orb.ini_th_fast > 0 && orb.ini_th_fast < 256, "ini_th_fast", "must be in [1, 255]");
  r.check(orb.min_th_fast > 0 && orb.min_th_fast <= orb.ini_th_fast, "min_th_fast",
          "must be in [1, ini_th_fast]");
  if (const auto bad = implausible_orb(orb)) r.check(false, bad->field, bad->problem);
  r.finish();
  return orb;
}

OutputConfig read_output(NodeReader& r) {
  OutputConfig out;
  out.dir = r.get("dir", out.dir);
  out.save_trajectory = r.get("save_trajectory", out.save_trajectory);
  out.save_keyframes = r.get("save_keyframes", out.save_keyframes);
  r.check(!out.dir.empty(), "dir", "must not be empty");
  r.finish();
  return out;
}

// The sections of a parsed config; `path` names it in errors.
Config config_from_yaml(const YAML::Node& root, const std::filesystem::path& path);

}  // namespace

Config load_config(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw file_error(path, "config file not found");
  {
    // Point users who pass an ORB-SLAM settings file here at camera.settings.
    std::ifstream in(path);
    std::string first;
    std::getline(in, first);
    if (first.rfind("%YAML:", 0) == 0) {
      throw file_error(path,
                       "this is an ORB-SLAM settings file (%YAML:1.0), not an lrd-slam config; "
                       "reference it from a config as 'camera: {settings: FILE}'");
    }
  }
  YAML::Node root;
  try {
    root = YAML::LoadFile(path.string());
  } catch (const YAML::ParserException& e) {
    throw line_error(path, static_cast<std::size_t>(e.mark.line) + 1, "YAML syntax error: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw file_error(path, std::string("cannot read config: ") + e.msg);
  }
  return config_from_yaml(root, path);
}

Config load_config_text(const std::string& text, const std::filesystem::path& origin) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw line_error(origin, static_cast<std::size_t>(e.mark.line) + 1, "YAML syntax error: " + e.msg);
  }
  if (!root.IsMap() && !root.IsNull()) throw file_error(origin, "a config is a mapping of sections");
  return config_from_yaml(root, origin);
}

namespace {

Config config_from_yaml(const YAML::Node& root, const std::filesystem::path& path) {
  Config cfg;
  cfg.file = path;
  NodeReader top(root, path, "");
  std::optional<features::OrbParams> settings_orb;
  if (top.has("camera")) {
    cfg.camera_given = true;
    NodeReader r = top.section("camera");
    cfg.camera = read_camera(r, settings_orb);
  }
  NodeReader features = top.section("features");
  cfg.features = read_features(features, settings_orb.value_or(features::OrbParams{}));
  NodeReader output = top.section("output");
  cfg.output = read_output(output);
  // Kept for their modules, which read and finish() them.
  cfg.tracking = top.section("tracking");
  cfg.mapping = top.section("mapping");
  cfg.dynamic = top.section("dynamic");
  cfg.segmentation = top.section("segmentation");
  cfg.dense = top.section("dense");
  cfg.occupancy = top.section("occupancy");
  cfg.loop_closing = top.section("loop_closing");
  top.finish();
  return cfg;
}

}  // namespace

}  // namespace lrd::config
