#include "lrd/synth/realism.h"

#include <algorithm>
#include <functional>
#include <nlohmann/json.hpp>
#include <utility>

#include "lrd/util/error.h"

namespace lrd::synth {
namespace {

// Each effect's switch, by the name `--realism-off` takes.
const std::vector<std::pair<std::string, bool RealismParams::*>>& effect_switches() {
  static const std::vector<std::pair<std::string, bool RealismParams::*>> switches = {
      {"auto_exposure", &RealismParams::auto_exposure},
      {"motion_blur", &RealismParams::motion_blur},
      {"rolling_shutter", &RealismParams::rolling_shutter},
      {"white_balance", &RealismParams::white_balance},
      {"vignetting", &RealismParams::vignetting},
      {"bayer", &RealismParams::bayer},
      {"sensor_noise", &RealismParams::sensor_noise},
      {"distortion", &RealismParams::distortion},
      {"calibration_error", &RealismParams::calibration_error},
      {"depth_registration", &RealismParams::depth_registration},
      {"depth_timing", &RealismParams::depth_timing},
      {"speckle_holes", &RealismParams::speckle_holes},
      {"depth_millimetres", &RealismParams::depth_millimetres},
      {"gt_noise", &RealismParams::gt_noise},
      {"gt_time_offset", &RealismParams::gt_time_offset},
      {"gt_mocap_rate", &RealismParams::gt_mocap_rate},
      {"camera_motion", &RealismParams::camera_motion},
  };
  return switches;
}

}  // namespace

bool RealismParams::is_clean() const {
  return std::none_of(effect_switches().begin(), effect_switches().end(),
                      [this](const auto& e) { return this->*(e.second); });
}

RealismParams realism_profile(std::string_view name) {
  RealismParams p;
  if (name == "clean") return p;
  if (name != "tum")
    throw Error("synth: unknown realism profile '" + std::string(name) + "' (valid: clean, tum)");
  p.profile = "tum";
  for (const auto& e : effect_switches()) p.*(e.second) = true;
  return p;
}

std::string realism_effect_list() {
  std::string names;
  for (const auto& e : realism_effects()) names += (names.empty() ? "" : ", ") + e;
  return names;
}

const std::vector<std::string>& realism_effects() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const auto& e : effect_switches()) out.push_back(e.first);
    return out;
  }();
  return names;
}

void disable_realism_effects(RealismParams& params, std::string_view comma_separated) {
  std::size_t from = 0;
  while (from <= comma_separated.size()) {
    const std::size_t comma = std::min(comma_separated.find(',', from), comma_separated.size());
    const std::string name(comma_separated.substr(from, comma - from));
    const auto& switches = effect_switches();
    const auto it =
        std::find_if(switches.begin(), switches.end(), [&](const auto& e) { return e.first == name; });
    if (it == switches.end())
      throw Error("synth: --realism-off: unknown effect '" + name + "' (valid: " + realism_effect_list() +
                  ")");
    params.*(it->second) = false;
    from = comma + 1;
  }
}

nlohmann::json realism_json(const RealismParams& p) {
  nlohmann::json effects;
  for (const auto& e : effect_switches()) effects[e.first] = p.*(e.second);
  const auto& d = p.rendered_distortion;
  return {
      {"profile", p.profile},
      {"effects", effects},
      {"exposure",
       {{"target_grey", p.target_grey},
        {"reference_s", p.reference_exposure},
        {"min_s", p.min_exposure},
        {"max_s", p.max_exposure},
        {"max_gain", p.max_gain}}},
      {"rolling_shutter", {{"readout_s", p.readout_time}}},
      {"subframes", {{"spacing_s", p.subframe_spacing}, {"max", p.max_subframes}}},
      {"white_balance_strength", p.white_balance_strength},
      {"vignetting_corner_loss", p.vignetting_corner_loss},
      {"sensor",
       {{"full_well_electrons", p.full_well_electrons}, {"read_noise_electrons", p.read_noise_electrons}}},
      {"rendered_distortion", {d.k1, d.k2, d.p1, d.p2, d.k3}},
      {"calibration_error",
       {{"focal_x", p.focal_error_x},
        {"focal_y", p.focal_error_y},
        {"cx_px", p.principal_point_error_x},
        {"cy_px", p.principal_point_error_y},
        {"k1", p.k1_error}}},
      {"registration_error_px", {p.registration_error_x, p.registration_error_y}},
      {"speckle_hole_rate", p.speckle_hole_rate},
      {"ground_truth",
       {{"position_sigma_m", p.gt_position_sigma},
        {"rotation_sigma_rad", p.gt_rotation_sigma},
        {"offset_s", p.gt_offset},
        {"rate_hz", p.gt_rate}}}};
}

camera::PinholeCamera calibrated_camera(const camera::PinholeCamera& truth, const RealismParams& p) {
  camera::PinholeCamera cam = truth;
  if (p.distortion) cam.distortion = p.rendered_distortion;
  // The readout time is part of the calibration (a rolling-shutter calibration estimates it).
  if (p.rolling_shutter) cam.readout_time = p.readout_time;
  if (p.calibration_error) {
    cam.fx *= 1.0 + p.focal_error_x;
    cam.fy *= 1.0 + p.focal_error_y;
    cam.cx += p.principal_point_error_x;
    cam.cy += p.principal_point_error_y;
    if (p.distortion) cam.distortion.k1 += p.k1_error;
    cam.bf = truth.bf * cam.fx / truth.fx;  // the baseline stays; bf follows fx
  }
  return cam;
}

}  // namespace lrd::synth
