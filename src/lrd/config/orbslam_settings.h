#pragma once
// Reader for ORB-SLAM2 / ORB-SLAM3 (File.version "1.0") settings files, read unchanged: they start
// with "%YAML:1.0", which cv::FileStorage understands and yaml-cpp does not.
#include <filesystem>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/features/orb_params.h"

namespace lrd::config {

struct Settings {
  camera::PinholeCamera camera;
  features::OrbParams orb;
};

// ORB-SLAM2 keys: Camera.fx fy cx cy (required), Camera.k1 k2 p1 p2 k3, Camera.width height fps,
// Camera.bf, ThDepth, DepthMapFactor (required), Camera.RGB, ORBextractor.nFeatures scaleFactor
// nLevels iniThFAST minThFAST.
// ORB-SLAM3 v1.0 keys: File.version "1.0", Camera.type "PinHole", Camera1.fx fy cx cy (required),
// Camera1.k1 k2 p1 p2 k3, Camera.width height (required), Camera.fps, Camera.RGB, Stereo.b or
// Camera.bf, Stereo.ThDepth or ThDepth, RGBD.DepthMapFactor or DepthMapFactor, ORBextractor.*.
// Keys not marked required default to the PinholeCamera / OrbParams defaults (distortion 0).
// Throws lrd::Error ("FILE: problem") for a missing file, a parse error, a missing required key,
// a non-numeric value or an unsupported camera type.
[[nodiscard]] Settings read_orbslam_settings(const std::filesystem::path& file);

}  // namespace lrd::config
