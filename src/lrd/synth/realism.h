#pragma once
// Realism profiles of the synthetic benchmark: `clean` is the plain renderer; `tum` adds what
// separates it from a Kinect v1 recording in the TUM RGB-D benchmark, each effect sized from a
// published figure where one exists (docs/synthetic-benchmark.md, "Realism profiles", lists value
// and source) and switchable on its own for ablations (`--realism-off EFFECT,...`).
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "lrd/camera/pinhole_camera.h"

namespace lrd::synth {

struct RealismParams {
  std::string profile = "clean";

  // Auto exposure: the exposure time follows the view's brightness (a longer one in a darker
  // view), up to the frame period; past it the sensor gain makes up the rest, with its noise.
  bool auto_exposure = false;
  double target_grey = 118.0;        // mean 8-bit level the exposure control aims at
  double reference_exposure = 0.01;  // s: the exposure at which a render's levels are what it drew
  double min_exposure = 0.002;       // s
  double max_exposure = 0.030;       // s: below the 33 ms frame period at 30 Hz
  double max_gain = 4.0;
  // Motion blur: colour integrated over the exposure from the true camera and actor motion.
  bool motion_blur = false;
  // Rolling shutter: rows read out top to bottom over `readout_time`, each at its own instant.
  bool rolling_shutter = false;
  double readout_time = 0.028;  // s (Kerl et al. 2015, TUM's rolling-shutter simulation)
  // Sub-frame renders over the span a frame integrates: at most this many, about this far apart.
  double subframe_spacing = 0.006;  // s
  int max_subframes = 9;

  // Auto white balance: channel gains pulled part way to grey-world from each view's mean colour,
  // so the colours of the same wall drift as the view changes.
  bool white_balance = false;
  double white_balance_strength = 0.35;  // 0: fixed gains, 1: full grey-world
  // Vignetting: brightness falls off towards the corners (relative loss at the corner).
  bool vignetting = false;
  double vignetting_corner_loss = 0.2;
  // Sensor: a Bayer mosaic (RGGB) demosaiced bilinearly, photon shot noise and read noise in
  // electrons, gamma and 8-bit quantisation.
  bool bayer = false;
  bool sensor_noise = false;
  double full_well_electrons = 4000.0;  // electrons at the 8-bit white level at unity gain
  double read_noise_electrons = 6.0;

  // Optics: the lens distortion is rendered (TUM's freiburg2 Kinect calibration)...
  bool distortion = false;
  camera::Distortion rendered_distortion{0.2312, -0.7849, -0.0033, -0.0001, 0.9172};
  // ...and the sequence's settings.yaml carries a calibration a little off, as a user's would.
  bool calibration_error = false;
  double focal_error_x = 0.006;  // relative
  double focal_error_y = -0.004;
  double principal_point_error_x = 1.5;  // px
  double principal_point_error_y = -2.0;
  double k1_error = -0.02;

  // Depth: registered to colour with a residual error (px), captured at the depth stream's own
  // instant, speckle holes, and stored in the driver's whole millimetres.
  bool depth_registration = false;
  double registration_error_x = 1.0;  // px
  double registration_error_y = -1.0;
  bool depth_timing = false;
  bool speckle_holes = false;
  double speckle_hole_rate = 0.002;  // share of pixels seeding a hole of up to 3 x 3
  bool depth_millimetres = false;

  // Ground truth: motion-capture noise, a time offset to the camera clock, and TUM's 100 Hz.
  bool gt_noise = false;
  double gt_position_sigma = 0.001;  // m, per axis
  double gt_rotation_sigma = 0.001;  // rad, per axis
  bool gt_time_offset = false;
  double gt_offset = 0.004;  // s
  bool gt_mocap_rate = false;
  double gt_rate = 100.0;  // Hz

  // Camera motion: each walking/sitting preset's path as fast, in translation and in rotation, as
  // the TUM fr3 sequence it mirrors (synth/motion_matching.h).
  bool camera_motion = false;

  [[nodiscard]] bool is_clean() const;
};

// `clean` or `tum`; anything else is an error naming the valid profiles.
[[nodiscard]] RealismParams realism_profile(std::string_view name);
// The effects `--realism-off` accepts, in the order the docs list them.
[[nodiscard]] const std::vector<std::string>& realism_effects();
// The same as one comma-separated line, for help texts and errors.
[[nodiscard]] std::string realism_effect_list();
// Turns off the comma-separated effects (an unknown name is an error listing the valid ones).
void disable_realism_effects(RealismParams& params, std::string_view comma_separated);
// What sequence.json records: the profile, every effect's switch and its parameters.
[[nodiscard]] nlohmann::json realism_json(const RealismParams& params);

// The calibration a user of a `tum` sequence gets (settings.yaml): the true camera with the
// rendered distortion, both a little off where calibration_error is on.
[[nodiscard]] camera::PinholeCamera calibrated_camera(const camera::PinholeCamera& truth,
                                                      const RealismParams& params);

}  // namespace lrd::synth
