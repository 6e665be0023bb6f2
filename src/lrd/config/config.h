#pragma once
// The lrd-slam YAML config (yaml-cpp): one top-level section per module. config/default.yaml
// documents every key and its default. Unknown sections and keys are errors.
//
// Sections whose modules are not written yet (tracking, mapping, dynamic, segmentation, dense)
// are accepted and kept unparsed as NodeReaders; the module reads its own section later with the
// same checks, e.g.
//   config::NodeReader r = cfg.tracking;
//   params.min_inliers = r.get("min_inliers", 15);
//   r.finish();  // "FILE:LINE: unknown key 'tracking.min_inlier' (did you mean 'min_inliers'?)"
#include <filesystem>
#include <string>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/config/node_reader.h"
#include "lrd/features/orb_params.h"

namespace lrd::config {

struct OutputConfig {
  std::filesystem::path dir = "output";  // relative paths are relative to the working directory
  bool save_trajectory = true;           // TUM-format CameraTrajectory.txt
  bool save_keyframes = true;            // TUM-format KeyFrameTrajectory.txt
};

struct Config {
  std::filesystem::path file;  // the file it was read from; empty for defaults
  camera::PinholeCamera camera = camera::camera_preset("tum3");
  bool camera_given = false;  // the file had a camera section (else the default above)
  features::OrbParams features;
  OutputConfig output;
  // Raw sections for modules still to come; empty readers when the section is absent.
  NodeReader tracking;
  NodeReader mapping;
  NodeReader dynamic;
  NodeReader segmentation;
  NodeReader dense;
  NodeReader occupancy;
  NodeReader loop_closing;
};

// Reads and validates `path`. Throws lrd::Error ("FILE[:LINE]: problem") for a missing file,
// YAML syntax errors, unknown sections or keys, wrong types and out-of-range values.
// camera: `preset: tum1|tum2|tum3|bonn`, or `settings: FILE` (ORB-SLAM2/3 settings, relative to the
// config file; its ORBextractor values then become the defaults of `features`), or explicit
// fx/fy/cx/cy; other fields given next to a preset or settings file override it. Without a
// camera section the camera is the tum3 preset.
[[nodiscard]] Config load_config(const std::filesystem::path& path);
// The same from YAML text (the Python module's dict configs); `origin` names it in errors and is
// where relative paths in it (camera.settings) are resolved from.
[[nodiscard]] Config load_config_text(const std::string& text, const std::filesystem::path& origin);

}  // namespace lrd::config
