#pragma once
// The synthetic benchmark's presets, mirroring TUM RGB-D fr3's dynamic sequences and the
// situations of Bonn RGB-D Dynamic's (crowds, a followed person, carried boxes, a balloon, people
// jumping in step). Their names are an interface: benchmarks, sweeps and tests refer to them.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lrd/synth/actor.h"
#include "lrd/synth/camera_motion.h"
#include "lrd/synth/motion_matching.h"
#include "lrd/synth/texture_library.h"

namespace lrd::synth {

enum class Cast {
  kNobody,
  kWalkers,
  kSitters,
  kPushAndCarry,
  kLoopWalkers,
  kTourWalkers,
  kSitStandUp,
  kCloseAndCut,
  kCrowd,
  kFollowed,
  kBoxBeside,
  kBoxInFront,
  kBalloon,
  kJumpers
};

struct PresetSpec {
  std::string name;
  int default_frames = 0;
  MotionKind motion = MotionKind::kStill;
  Cast cast = Cast::kNobody;
  std::string description;
  // Left out of the segmentation training data, whose draw over the presets (voc_exporter) stays
  // the one FNet-lite was trained on: the long presets (bench_scale) and those added after it.
  bool held_out = false;
};

[[nodiscard]] const std::vector<PresetSpec>& preset_specs();
// Throws lrd::Error listing the valid names.
[[nodiscard]] const PresetSpec& find_preset(const std::string& name);
// The TUM fr3 sequence whose hand-held statistics the realism profile gives this preset's camera:
// the one it mirrors, or for the Bonn-style presets standing where the walking presets' camera
// stands, TUM's hand-held walking_xyz or walking_static (Bonn publishes no velocity statistics);
// empty for the others.
[[nodiscard]] std::string motion_model(const PresetSpec& spec);
// That sequence's published mean speeds (tum_fr3_motion), if there is one.
[[nodiscard]] std::optional<MotionTarget> motion_target(const PresetSpec& spec);

// Everything that moves in a preset, for a given seed.
struct SceneScript {
  std::unique_ptr<CameraMotion> camera;
  std::vector<std::unique_ptr<Actor>> actors;
};

// `session`: the camera's standpoint (CameraMotion); the people are the same in every session.
// `hand_held`: the camera moves as fast as the TUM fr3 sequence the preset mirrors, if it mirrors
// one (synth/motion_matching.h; the realism profile's camera_motion effect).
[[nodiscard]] SceneScript build_scene_script(const PresetSpec& spec, const TextureLibrary& tex,
                                             std::uint64_t seed, double fps, int session = 1,
                                             bool hand_held = false);

}  // namespace lrd::synth
