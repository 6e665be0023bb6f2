#pragma once
// One synthetic dynamic RGB-D sequence: the room, a preset's camera motion and actors, the
// renderer and the sensor model. Any frame renders independently of the others, so frames can be
// produced in parallel and in any order with byte-identical results.
#include <Eigen/Geometry>
#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/dense/point_cloud.h"
#include "lrd/io/trajectory.h"
#include "lrd/synth/presets.h"
#include "lrd/synth/rasterizer.h"
#include "lrd/synth/realism.h"
#include "lrd/synth/realistic_camera.h"
#include "lrd/synth/sensor_model.h"
#include "lrd/synth/texture_library.h"

namespace lrd::synth {

struct SynthOptions {
  std::string preset = "walking_xyz";
  std::uint64_t seed = 1;
  int frames = -1;           // < 0: the preset's default length
  bool motion_blur = false;  // average sub-frames over the exposure (the clean profile's blur)
  int blur_subframes = 5;
  double exposure = 1.0 / 60.0;  // s
  // Frames [blank_from, blank_from + blank_count) are black with no depth (a covered lens): the
  // camera keeps moving meanwhile, so tracking is lost and must relocalize when the view returns.
  int blank_from = -1;
  int blank_count = 0;
  // The camera runs the preset's path this many times faster (e.g. static_loop's two laps in
  // 400 frames at 2.5: a loop closes within a short test); 1 is the benchmark.
  double camera_speed = 1.0;
  // Map-file sessions (docs/map-files.md): 1 is the preset's camera path; 2 and 3 see the same room
  // and people, with the same seed, from another standpoint (CameraMotion), in the same world
  // frame.
  int session = 1;
  // `--realism` (docs/synthetic-benchmark.md): `clean` is the plain renderer; `tum` renders as a
  // Kinect v1 in TUM's recordings.
  RealismParams realism;
  [[nodiscard]] bool blanked(int i) const {
    return blank_from >= 0 && i >= blank_from && i < blank_from + blank_count;
  }
};

struct SynthFrame {
  int index = 0;
  double timestamp = 0.0;        // rgb
  double depth_timestamp = 0.0;  // depth is stamped apart from rgb, as with a real Kinect
  Eigen::Isometry3d pose;        // ground truth camera-to-world at `timestamp`
  cv::Mat rgb;                   // CV_8UC3 BGR
  cv::Mat depth;                 // CV_16U, factor 5000
  cv::Mat mask;                  // CV_8U MaskLabel values
  cv::Mat voc_class;             // CV_8U Pascal VOC class of every pixel
  cv::Mat static_rgb;            // same view with the actors removed
  cv::Mat static_depth;
};

class SyntheticSequence {
 public:
  explicit SyntheticSequence(const SynthOptions& options);
  // Shares an already loaded texture library (loading the photographs takes about a second).
  SyntheticSequence(const SynthOptions& options, std::shared_ptr<const TextureLibrary> textures);
  ~SyntheticSequence();

  [[nodiscard]] int size() const { return frames_; }
  [[nodiscard]] const PresetSpec& spec() const { return spec_; }
  // The calibration a user of the sequence has (settings.yaml): under the `tum` profile, the lens
  // distortion rendered and a small calibration error; otherwise the camera that rendered it.
  [[nodiscard]] const camera::PinholeCamera& camera() const { return calibration_; }
  // The pinhole camera the renderer draws with.
  [[nodiscard]] const camera::PinholeCamera& true_camera() const { return camera_; }
  [[nodiscard]] const SynthOptions& options() const { return options_; }
  [[nodiscard]] const TextureLibrary& textures() const { return *textures_; }
  [[nodiscard]] std::vector<std::string> actor_descriptions() const;
  [[nodiscard]] const CameraMotion& camera_motion() const { return *script_.camera; }

  [[nodiscard]] double timestamp(int i) const;
  [[nodiscard]] double depth_timestamp(int i) const;
  [[nodiscard]] Eigen::Isometry3d pose(int i) const;
  // Every frame's pose at its colour timestamp: groundtruth.txt, and a streamed run's ground truth.
  [[nodiscard]] io::Trajectory ground_truth() const;
  // What render() produces: everything the sequence folder holds, or only what a camera gives
  // (rgb, depth, mask; no static view), for a run that streams frames (SyntheticSource).
  enum class Views { All, CameraOnly };
  // Renders frame i (thread-safe). rgb, depth and mask do not depend on `views`.
  [[nodiscard]] SynthFrame render(int i, Views views = Views::All) const;
  // Samples of the static room's surfaces in world coordinates (scene.ply), about one per 4 cm^2.
  [[nodiscard]] dense::PointCloud scene_samples() const;

  static constexpr double kFirstTimestamp = 1700000000.0;
  // Textures of the room do not depend on the sequence seed: every seed sees the same room.
  static std::shared_ptr<const TextureLibrary> load_textures();

 private:
  [[nodiscard]] Eigen::Isometry3d camera_pose(double t) const;  // t: seconds from the first frame
  // The room alone and the room with the actors, seen at t (seconds from the first frame).
  void render_passes(double t, RenderBuffers& static_pass, RenderBuffers& full_pass) const;
  // render() under a realism profile other than clean (synthetic_sequence_realism.cc).
  [[nodiscard]] SynthFrame render_realistic(SynthFrame f, Views views) const;
  // ground_truth() with the motion-capture effects of the realism profile.
  [[nodiscard]] io::Trajectory motion_capture() const;
  SynthOptions options_;
  const PresetSpec& spec_;
  int frames_;
  camera::PinholeCamera camera_;
  camera::PinholeCamera calibration_;
  std::shared_ptr<const TextureLibrary> textures_;
  TriangleSoup room_;
  SceneScript script_;
  std::unique_ptr<Rasterizer> rasterizer_;
  std::unique_ptr<SensorModel> sensor_;
  std::unique_ptr<RealisticCamera> realistic_;  // null under the clean profile
};

}  // namespace lrd::synth
