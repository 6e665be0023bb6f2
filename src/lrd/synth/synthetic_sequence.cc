#include "lrd/synth/synthetic_sequence.h"

#include <cmath>

#include "lrd/synth/room_scene.h"
#include "lrd/synth/scene_sampler.h"
#include "lrd/util/error.h"

namespace lrd::synth {
namespace {

// Deterministic per-frame offsets in [-1, 1].
double frame_hash(std::uint64_t seed, int i, std::uint64_t stream) {
  std::uint64_t x =
      seed * 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(i) * 0xBF58476D1CE4E5B9ull + stream;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  x ^= x >> 31;
  return static_cast<double>(x >> 11) * 0x1.0p-52 - 1.0;
}

constexpr std::uint64_t kRoomTextureSeed = 2024;

}  // namespace

std::shared_ptr<const TextureLibrary> SyntheticSequence::load_textures() {
  return std::make_shared<const TextureLibrary>(kRoomTextureSeed);
}

SyntheticSequence::SyntheticSequence(const SynthOptions& options)
    : SyntheticSequence(options, load_textures()) {}

SyntheticSequence::SyntheticSequence(const SynthOptions& options,
                                     std::shared_ptr<const TextureLibrary> textures)
    : options_(options),
      spec_(find_preset(options.preset)),
      camera_(camera::camera_preset("tum3")),
      textures_(std::move(textures)) {
  frames_ = options.frames < 0 ? spec_.default_frames : options.frames;
  if (frames_ == 0) throw Error("synth: --frames must be at least 1");
  room_ = build_room(*textures_);
  script_ = build_scene_script(spec_, *textures_, options.seed, camera_.fps, options.session,
                               options.realism.camera_motion);
  rasterizer_ = std::make_unique<Rasterizer>(camera_, *textures_);
  sensor_ = std::make_unique<SensorModel>(camera_, SensorParams{}, options.seed);
  calibration_ = calibrated_camera(camera_, options.realism);
  if (!options.realism.is_clean())
    realistic_ = std::make_unique<RealisticCamera>(camera_, options.realism, sensor_->params().rgb_blur_sigma,
                                                   sensor_->noise());
}

SyntheticSequence::~SyntheticSequence() = default;

std::vector<std::string> SyntheticSequence::actor_descriptions() const {
  std::vector<std::string> out;
  for (const auto& a : script_.actors) out.push_back(a->describe());
  return out;
}

double SyntheticSequence::timestamp(int i) const {
  // 30 Hz with a fraction of a millisecond of capture jitter, like a real camera driver.
  return kFirstTimestamp + i / camera_.fps + 0.0004 * frame_hash(options_.seed, i, 11);
}

double SyntheticSequence::depth_timestamp(int i) const {
  // Depth and colour are separate streams: a few milliseconds apart (TUM's are up to ~20 ms).
  return timestamp(i) + 0.008 * frame_hash(options_.seed, i, 12);
}

Eigen::Isometry3d SyntheticSequence::camera_pose(double t) const {
  // --camera-speed: the camera's clock runs faster; the people keep theirs (x 1.0 is exact).
  return script_.camera->pose_at(t * options_.camera_speed);
}

Eigen::Isometry3d SyntheticSequence::pose(int i) const {
  return camera_pose(timestamp(i) - kFirstTimestamp);
}

io::Trajectory SyntheticSequence::ground_truth() const {
  const RealismParams& r = options_.realism;
  if (r.gt_noise || r.gt_time_offset || r.gt_mocap_rate) return motion_capture();
  io::Trajectory gt;
  gt.reserve(static_cast<std::size_t>(frames_));
  for (int i = 0; i < frames_; ++i) gt.push_back({timestamp(i), pose(i)});
  return gt;
}

void SyntheticSequence::render_passes(double t, RenderBuffers& static_pass, RenderBuffers& full_pass) const {
  const Eigen::Isometry3f T_wc = camera_pose(t).cast<float>();
  static_pass = rasterizer_->make_buffers();
  rasterizer_->draw(room_.triangles(), T_wc, static_pass);
  full_pass = static_pass.clone();
  TriangleSoup actors;
  for (const auto& a : script_.actors) a->add_geometry(t, actors);
  rasterizer_->draw(actors.triangles(), T_wc, full_pass);
  Rasterizer::finish(static_pass);
  Rasterizer::finish(full_pass);
}

SynthFrame SyntheticSequence::render(int i, Views views) const {
  if (i < 0 || i >= frames_) throw Error("synth: frame index out of range");
  SynthFrame f;
  f.index = i;
  f.timestamp = timestamp(i);
  f.depth_timestamp = depth_timestamp(i);
  const double t = f.timestamp - kFirstTimestamp;
  f.pose = camera_pose(t);
  if (realistic_) return render_realistic(std::move(f), views);

  RenderBuffers static_pass, full_pass;
  render_passes(t, static_pass, full_pass);
  cv::Mat color = full_pass.color, static_color = static_pass.color;
  if (options_.motion_blur && options_.blur_subframes > 1) {
    // Average colour over the exposure; depth and masks stay those of the frame's instant.
    cv::Mat acc(color.size(), CV_32FC3, cv::Scalar::all(0)), acc_static = acc.clone();
    for (int k = 0; k < options_.blur_subframes; ++k) {
      const double tk =
          t + options_.exposure * (static_cast<double>(k) / (options_.blur_subframes - 1) - 0.5);
      RenderBuffers s, d;
      render_passes(tk, s, d);
      cv::Mat tmp;
      d.color.convertTo(tmp, CV_32FC3);
      acc += tmp;
      s.color.convertTo(tmp, CV_32FC3);
      acc_static += tmp;
    }
    acc.convertTo(color, CV_8UC3, 1.0 / options_.blur_subframes);
    acc_static.convertTo(static_color, CV_8UC3, 1.0 / options_.blur_subframes);
  }
  f.rgb = sensor_->rgb_image(color, i);
  f.depth = sensor_->depth_image(full_pass, i);
  if (views == Views::All) {
    f.static_rgb = sensor_->rgb_image(static_color, i);
    f.static_depth = sensor_->depth_image(static_pass, i);
  }
  f.mask = full_pass.label;
  f.voc_class = full_pass.voc_class;
  if (options_.blanked(i)) {
    f.rgb.setTo(cv::Scalar::all(0));
    f.depth.setTo(cv::Scalar::all(0));
  }
  return f;
}

dense::PointCloud SyntheticSequence::scene_samples() const {
  return sample_surfaces(room_, *textures_);
}

}  // namespace lrd::synth
