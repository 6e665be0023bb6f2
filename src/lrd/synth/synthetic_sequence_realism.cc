// SyntheticSequence under a realism profile other than `clean` (docs/synthetic-benchmark.md): the
// colour camera's exposure, shutter and sensor (RealisticCamera), depth at its own instant and
// registered to the colour image, and ground truth as a motion-capture system records it.
#include <cmath>

#include "lrd/synth/synthetic_sequence.h"

namespace lrd::synth {
namespace {

constexpr std::uint64_t kMocapStream = 31;

}  // namespace

SynthFrame SyntheticSequence::render_realistic(SynthFrame f, Views views) const {
  const RealismParams& r = options_.realism;
  const double t = f.timestamp - kFirstTimestamp;
  RenderBuffers static_pass, full_pass;
  render_passes(t, static_pass, full_pass);
  // The exposure control sees the view (actors included); the actor-free view shares its settings.
  const RealisticCamera::Exposure exposure = realistic_->expose(full_pass.color);
  const RealisticCamera::ShutterPlan plan = realistic_->shutter(t, exposure);
  std::vector<cv::Mat> full_colour, static_colour;
  if (plan.times.size() == 1) {
    full_colour = {full_pass.color};
    static_colour = {static_pass.color};
  } else {
    for (double tk : plan.times) {
      if (tk == t) {  // the middle instant: the frame's own render
        full_colour.push_back(full_pass.color);
        static_colour.push_back(static_pass.color);
        continue;
      }
      RenderBuffers s, d;
      render_passes(tk, s, d);
      full_colour.push_back(d.color);
      static_colour.push_back(s.color);
    }
  }
  // Depth: the depth stream's own instant (TUM stamps depth and colour apart).
  RenderBuffers static_depth_pass = static_pass, full_depth_pass = full_pass;
  if (r.depth_timing && f.depth_timestamp != f.timestamp)
    render_passes(f.depth_timestamp - kFirstTimestamp, static_depth_pass, full_depth_pass);
  const double factor = camera_.depth_map_factor;
  const int i = f.index;
  f.rgb = realistic_->develop(realistic_->integrate(full_colour, plan), exposure, i);
  f.depth = realistic_->register_depth(sensor_->depth_image(full_depth_pass, i), i, factor);
  if (views == Views::All) {
    f.static_rgb = realistic_->develop(realistic_->integrate(static_colour, plan), exposure, i);
    f.static_depth = realistic_->register_depth(sensor_->depth_image(static_depth_pass, i), i, factor);
  }
  f.mask = realistic_->warp_labels(full_pass.label);
  f.voc_class = realistic_->warp_labels(full_pass.voc_class);
  if (options_.blanked(i)) {
    f.rgb.setTo(cv::Scalar::all(0));
    f.depth.setTo(cv::Scalar::all(0));
  }
  return f;
}

io::Trajectory SyntheticSequence::motion_capture() const {
  const RealismParams& r = options_.realism;
  // Stamps: the motion-capture clock (TUM: 100 Hz from before the first to after the last image),
  // or the images' own.
  std::vector<double> stamps;
  if (r.gt_mocap_rate) {
    const double first = timestamp(0) - 0.1, last = timestamp(frames_ - 1) + 0.1;
    for (int j = 0; first + j / r.gt_rate <= last; ++j) stamps.push_back(first + j / r.gt_rate);
  } else {
    for (int i = 0; i < frames_; ++i) stamps.push_back(timestamp(i));
  }
  io::Trajectory gt;
  gt.reserve(stamps.size());
  for (std::size_t j = 0; j < stamps.size(); ++j) {
    // The motion-capture clock runs behind the camera's by gt_offset: its stamp s holds the
    // camera's pose at s + gt_offset.
    const double offset = r.gt_time_offset ? r.gt_offset : 0.0;
    Eigen::Isometry3d pose = camera_pose(stamps[j] + offset - kFirstTimestamp);
    if (r.gt_noise) {
      const auto noise = sensor_->noise().gaussian(static_cast<int>(j), kMocapStream);
      const Eigen::Vector3d dp(noise(0), noise(1), noise(2)), dr(noise(3), noise(4), noise(5));
      pose.translation() += r.gt_position_sigma * dp;
      const Eigen::Vector3d angle = r.gt_rotation_sigma * dr;
      pose.linear() =
          (Eigen::AngleAxisd(angle.norm(), angle.norm() > 0 ? angle.normalized() : Eigen::Vector3d::UnitX()) *
           Eigen::Quaterniond(pose.linear()))
              .toRotationMatrix();
    }
    gt.push_back({stamps[j], pose});
  }
  return gt;
}

}  // namespace lrd::synth
