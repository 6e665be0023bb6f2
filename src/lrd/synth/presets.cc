#include "lrd/synth/presets.h"

#include <cmath>
#include <map>

#include "lrd/synth/approaching_actor.h"
#include "lrd/synth/balloon_actor.h"
#include "lrd/synth/box_mover_actor.h"
#include "lrd/synth/jumping_actor.h"
#include "lrd/synth/motion_matching.h"
#include "lrd/synth/portable_random.h"
#include "lrd/synth/room_scene.h"
#include "lrd/synth/seated_actor.h"
#include "lrd/synth/standing_up_actor.h"
#include "lrd/synth/walking_actor.h"
#include "lrd/util/error.h"

namespace lrd::synth {
namespace {

// The seed is mixed so that actors and camera (seeded alike) draw different streams.
class Draw : public PortableRandom {
 public:
  explicit Draw(std::uint64_t seed) : PortableRandom(seed ^ 0xC0FFEE1234ull) {}
};

Appearance random_look(const TextureLibrary& tex, Draw& d, int index) {
  static const char* shirts[] = {"plaid_red",     "plaid_blue",    "stripes_shirt",
                                 "stripes_green", "clothes_print", "clothes_flowers"};
  static const char* trousers[] = {"denim", "trousers_dark"};
  static const char* skins[] = {"skin_light", "skin_dark"};
  static const char* hairs[] = {"hair_dark", "hair_brown"};
  Appearance a;
  // Different people get different shirts even when the draw coincides.
  a.shirt = tex.id(shirts[(d.pick(6) + static_cast<std::size_t>(index) * 2) % 6]);
  a.trousers = tex.id(trousers[d.pick(2)]);
  a.skin = tex.id(skins[d.pick(2)]);
  a.hair = tex.id(hairs[d.pick(2)]);
  a.shoes = tex.id("shoe");
  a.height = d.uniform(1.62f, 1.88f);
  a.girth = d.uniform(0.9f, 1.12f);
  return a;
}

using P = Eigen::Vector2f;

}  // namespace

const std::vector<PresetSpec>& preset_specs() {
  static const std::vector<PresetSpec> specs = {
      {"walking_static", 743, MotionKind::kStill, Cast::kWalkers,
       "two people walk around the desk; camera nearly still"},
      {"walking_xyz", 859, MotionKind::kXyz, Cast::kWalkers,
       "two people walk; camera translates along x, y, z"},
      {"walking_rpy", 910, MotionKind::kRpy, Cast::kWalkers,
       "two people walk; camera rotates in roll, pitch, yaw"},
      {"walking_halfsphere", 1067, MotionKind::kHalfsphere, Cast::kWalkers,
       "two people walk; camera moves on a half sphere of ~1 m diameter"},
      {"sitting_static", 707, MotionKind::kStill, Cast::kSitters,
       "two seated people talk and gesture; camera nearly still"},
      {"sitting_xyz", 1261, MotionKind::kXyz, Cast::kSitters,
       "two seated people; camera translates along x, y, z"},
      {"sitting_halfsphere", 1110, MotionKind::kHalfsphere, Cast::kSitters,
       "two seated people; camera moves on a half sphere"},
      {"static_xyz", 1000, MotionKind::kXyz, Cast::kNobody, "empty room; camera translates along x, y, z"},
      {"static_halfsphere", 1000, MotionKind::kHalfsphere, Cast::kNobody,
       "empty room; camera on a half sphere"},
      {"static_loop", 1000, MotionKind::kLoop, Cast::kNobody, "empty room; camera circles the room twice"},
      {"walking_loop", 1000, MotionKind::kLoop, Cast::kLoopWalkers,
       "two people walk around the room while the camera circles it twice"},
      {"walking_pushed", 900, MotionKind::kXyz, Cast::kPushAndCarry,
       "a person pushes a chair, another carries a box; camera translates"},
      {"sitting_standup", 900, MotionKind::kXyz, Cast::kSitStandUp,
       "two seated people; after 8-9 s one stands up and walks out of the view; camera translates along x, "
       "y, z",
       true},
      {"walking_close", 900, MotionKind::kStill, Cast::kCloseAndCut,
       "one person walks straight at the camera and fills most of the view for a moment, again and again; "
       "another carries a box round a loop at the image's right border; camera nearly still",
       true},
      {"walking_long", 21600, MotionKind::kTour, Cast::kTourWalkers,
       "the long preset (12 min): three people walk around the room, one against the others, while the "
       "camera tours it, 36 laps whose radius and height drift (revisits, loops); bench_scale's sequence",
       true},
      {"walking_circle", 21600, MotionKind::kCircle, Cast::kTourWalkers,
       "walking_long's people while the camera circles the room on the same 0.65 m circle for 36 laps "
       "(12 min): a map that should stop growing after the first laps",
       true},
      // Bonn RGB-D Dynamic's situations (Palazzolo et al., IROS 2019), about as long as its sequences.
      {"crowd", 900, MotionKind::kXyz, Cast::kCrowd,
       "Bonn crowd: five people cross the view in different directions, 1.1-3 m from the camera, "
       "together covering up to ~60 % of it; hand-held camera translates",
       true},
      {"person_tracking", 900, MotionKind::kFollow, Cast::kFollowed,
       "Bonn person_tracking: the camera is carried 1-2.5 m behind one person walking round the middle of "
       "the "
       "room and keeps them in the middle of the image for the whole sequence",
       true},
      {"moving_box", 900, MotionKind::kXyz, Cast::kBoxBeside,
       "Bonn moving_nonobstructing_box: a person carries a box across the room in front of the desk, puts "
       "it down, walks away, later carries it back; hand-held camera translates",
       true},
      {"moving_box_obstructing", 900, MotionKind::kStill, Cast::kBoxInFront,
       "Bonn moving_obstructing_box: a person carries a box across the view 0.8 m in front of the camera, "
       "hiding most of the room while it passes; hand-held camera nearly still",
       true},
      {"balloon", 600, MotionKind::kXyz, Cast::kBalloon,
       "Bonn balloon: two people throw a printed balloon to each other across the view (no class a "
       "segmentation network knows); hand-held camera translates",
       true},
      {"synchronous", 600, MotionKind::kStill, Cast::kJumpers,
       "Bonn synchronous: three people jump on the spot in step, in sets of five; hand-held camera nearly "
       "still",
       true},
  };
  return specs;
}

const PresetSpec& find_preset(const std::string& name) {
  std::string names;
  for (const auto& s : preset_specs()) {
    if (s.name == name) return s;
    names += (names.empty() ? "" : ", ") + s.name;
  }
  throw Error("unknown synthetic preset '" + name + "' (valid: " + names + ")");
}

std::string motion_model(const PresetSpec& spec) {
  static const std::map<std::string, std::string> bonn = {{"crowd", "walking_xyz"},
                                                          {"moving_box", "walking_xyz"},
                                                          {"moving_box_obstructing", "walking_static"},
                                                          {"balloon", "walking_xyz"},
                                                          {"synchronous", "walking_static"}};
  if (tum_fr3_motion(spec.name)) return spec.name;
  const auto it = bonn.find(spec.name);
  return it == bonn.end() ? std::string() : it->second;
}

std::optional<MotionTarget> motion_target(const PresetSpec& spec) {
  const std::string model = motion_model(spec);
  if (model.empty()) return std::nullopt;
  return tum_fr3_motion(model);
}

SceneScript build_scene_script(const PresetSpec& spec, const TextureLibrary& tex, std::uint64_t seed,
                               double fps, int session, bool hand_held) {
  SceneScript script;
  const double duration = spec.default_frames / fps;
  script.camera = std::make_unique<CameraMotion>(spec.motion, duration, seed, session);
  const auto target = motion_target(spec);
  if (hand_held && target) {
    // Sized on the path session 1 renders, so that every map-file session moves alike.
    const CameraMotion first(spec.motion, duration, seed, 1);
    script.camera->set_hand_held(match_motion(first, *target, duration, fps));
  }
  Draw d(seed);
  // Paths in front of the camera (which stands near x = 2.2 looking at the desk at x = 4.2..5.0,
  // y = 1.5..3.5). As in TUM's walking sequences, people pass within 1-2 m of the camera and
  // often cover 20-50 % of the image: one paces to and fro about 1.2 m in front of the camera,
  // turning inside the view, the other walks round the desk.
  const std::vector<P> around_desk = {P(3.95f, 0.8f), P(3.95f, 4.2f), P(5.62f, 4.35f), P(5.66f, 0.65f)};
  const std::vector<P> front_loop = {P(3.25f, 1.95f), P(3.27f, 3.05f), P(3.5f, 3.07f), P(3.48f, 1.93f)};
  const std::vector<P> room_loop = {P(1.2f, 4.05f), P(4.05f, 4.1f), P(4.0f, 0.9f), P(1.25f, 0.95f)};
  auto walker = [&](const std::vector<P>& path, float start_fraction, CarriedProp prop, int index,
                    float speed) {
    WalkingParams w;
    w.waypoints = path;
    w.speed = speed * d.uniform(0.9f, 1.1f);
    w.speed_variation = d.uniform(0.35f, 0.7f);
    w.phase = d.uniform(0.0f, 6.283f);
    w.prop = prop;
    ClosedPath p(path);
    w.start = (start_fraction + d.uniform(0.0f, 0.2f)) * p.length();
    script.actors.push_back(std::make_unique<WalkingActor>(w, random_look(tex, d, index), tex,
                                                           "person " + std::to_string(index + 1)));
  };
  auto person = [&](int index) { return random_look(tex, d, index); };
  switch (spec.cast) {
    case Cast::kNobody:
      break;
    case Cast::kCrowd:
      // Two cross 1.1-1.8 m from the camera in opposite directions, one walks round the
      // desk, one diagonally away and back, one towards the camera and back.
      walker({P(3.3f, 0.8f), P(3.3f, 4.2f), P(3.55f, 4.2f), P(3.55f, 0.8f)}, 0.0f, CarriedProp::kNone, 0,
             0.9f);
      walker({P(3.95f, 4.2f), P(3.95f, 0.8f), P(3.75f, 0.8f), P(3.75f, 4.2f)}, 0.5f, CarriedProp::kNone, 1,
             0.8f);
      walker(around_desk, 0.3f, CarriedProp::kNone, 2, 0.85f);
      walker({P(3.2f, 1.2f), P(4.0f, 3.9f), P(3.85f, 4.1f), P(3.05f, 1.4f)}, 0.2f, CarriedProp::kNone, 3,
             0.8f);
      walker({P(4.0f, 2.1f), P(3.6f, 2.75f), P(3.7f, 2.9f), P(4.05f, 2.3f)}, 0.7f, CarriedProp::kNone, 4,
             0.7f);
      break;
    case Cast::kFollowed: {
      // One person walks a loop round the middle of the room; the camera follows them
      // (MotionKind::kFollow), seeing the room 1.3-3 m beyond them rather than a wall up close.
      const std::vector<P> middle_loop = {P(1.75f, 3.5f), P(3.75f, 3.55f), P(3.7f, 1.45f), P(1.8f, 1.5f)};
      WalkingParams w;
      w.waypoints = middle_loop;
      w.speed = 0.8f * d.uniform(0.95f, 1.05f);
      w.speed_variation = 0.3f;
      w.phase = d.uniform(0.0f, 6.283f);
      w.start = 0.35f * ClosedPath(middle_loop).length();
      auto followed = std::make_unique<WalkingActor>(w, person(0), tex, "person 1");
      const WalkingActor* target = followed.get();
      script.camera->set_follow([target](double t) { return target->floor_position(t); });
      script.actors.push_back(std::move(followed));
      break;
    }
    case Cast::kBoxBeside:
    case Cast::kBoxInFront: {
      // The box rests at one end of a line across the view, is carried to the other end, rests,
      // and is carried back: in front of the desk 1.7 m from the camera (beside its view of the
      // room), or 0.85 m from it (hiding most of the room while it passes).
      const bool in_front = spec.cast == Cast::kBoxInFront;
      BoxMoveParams b;
      b.home = in_front ? P(3.45f, 0.7f) : P(3.2f, 0.6f);
      b.spot_a = in_front ? P(3.05f, 1.75f) : P(3.85f, 1.55f);
      b.spot_b = in_front ? P(3.05f, 3.25f) : P(3.85f, 3.45f);
      b.speed = 0.75f * d.uniform(0.9f, 1.1f);
      b.wait = d.uniform(2.5, 3.5);
      b.start = d.uniform(0.0, 1.0);
      b.phase = d.uniform(0.0f, 6.283f);
      script.actors.push_back(std::make_unique<BoxMoverActor>(b, person(0), tex, "person 1"));
      break;
    }
    case Cast::kBalloon: {
      BalloonParams b;
      b.first = P(3.95f, 1.6f);
      b.second = P(3.95f, 3.4f);
      b.flight = d.uniform(1.4, 1.8);
      b.hold = d.uniform(0.5, 0.8);
      b.start = d.uniform(0.0, 2.0);
      b.phase = d.uniform(0.0f, 6.283f);
      const Appearance first = person(0);
      script.actors.push_back(std::make_unique<BalloonActor>(b, first, person(1), tex, "persons 1 and 2"));
      break;
    }
    case Cast::kJumpers: {
      // In step: the same cycle and start for all three, facing the camera.
      const double start = d.uniform(0.0, 1.0);
      const std::vector<P> spots = {P(3.7f, 1.75f), P(4.0f, 2.5f), P(3.7f, 3.25f)};
      for (std::size_t i = 0; i < spots.size(); ++i) {
        JumpParams j;
        j.spot = spots[i];
        j.yaw = static_cast<float>(M_PI) + d.uniform(-0.2f, 0.2f);
        j.height = d.uniform(0.16f, 0.24f);
        j.start = start;
        j.phase = d.uniform(0.0f, 6.283f);
        const int idx = static_cast<int>(i);
        script.actors.push_back(
            std::make_unique<JumpingActor>(j, person(idx), "person " + std::to_string(idx + 1)));
      }
      break;
    }
    case Cast::kWalkers:
      walker(around_desk, 0.0f, CarriedProp::kNone, 0, 0.9f);
      walker(front_loop, 0.45f, CarriedProp::kNone, 1, 0.8f);
      break;
    case Cast::kSitters: {
      const auto seats = RoomLayout::seat_poses();
      for (std::size_t i = 0; i < seats.size(); ++i) {
        const int idx = static_cast<int>(i);
        script.actors.push_back(std::make_unique<SeatedActor>(seats[i], random_look(tex, d, idx),
                                                              d.uniform(0.0f, 6.283f), d.uniform(0.7f, 1.0f),
                                                              "person " + std::to_string(idx + 1)));
      }
      break;
    }
    case Cast::kSitStandUp: {
      // Person 1 sits long enough to be mapped as background, then gets up, walks round the end of
      // the desk and out of the view to the right, and stays there; person 2 sits on.
      const auto seats = RoomLayout::seat_poses();
      const Eigen::Vector3f seat = seats[0].translation();
      SeatedActor first(seats[0], random_look(tex, d, 0), d.uniform(0.0f, 6.283f), d.uniform(0.7f, 1.0f),
                        "person 1");
      const std::vector<P> exit = {P(seat.x(), seat.y() - 0.15f), P(5.45f, 1.6f), P(5.35f, 0.95f),
                                   P(4.0f, 0.9f), P(2.6f, 0.95f)};
      script.actors.push_back(
          std::make_unique<StandingUpActor>(std::move(first), d.uniform(8.0f, 9.0f), exit, 0.8f, "person 1"));
      script.actors.push_back(std::make_unique<SeatedActor>(
          seats[1], random_look(tex, d, 1), d.uniform(0.0f, 6.283f), d.uniform(0.7f, 1.0f), "person 2"));
      break;
    }
    case Cast::kCloseAndCut: {
      // Person 1 walks from the desk straight at the camera (which stands at x = 2.2, y = 2.5) and
      // stands 0.6 m from it, filling most of the view; person 2 carries a box round a small loop
      // to the right, 0.7-1.7 m from the camera: cut by the border, legs or head out of the view.
      ApproachParams a;
      a.far = P(4.0f, 2.45f);
      a.near = P(2.65f, 2.5f);
      a.speed = 0.8f * d.uniform(0.9f, 1.1f);
      a.hold = 1.5;
      a.wait = 3.0;
      a.start = d.uniform(0.0f, 2.0f);
      a.phase = d.uniform(0.0f, 6.283f);
      script.actors.push_back(std::make_unique<ApproachingActor>(a, random_look(tex, d, 0), "person 1"));
      walker({P(2.95f, 1.45f), P(3.05f, 2.15f), P(3.9f, 2.1f), P(3.8f, 1.35f)}, 0.0f,
             CarriedProp::kCarriedBox, 1, 0.6f);
      break;
    }
    case Cast::kPushAndCarry:
      walker(front_loop, 0.0f, CarriedProp::kPushedChair, 0, 0.55f);
      walker(around_desk, 0.5f, CarriedProp::kCarriedBox, 1, 0.75f);
      break;
    case Cast::kLoopWalkers:
      walker(room_loop, 0.0f, CarriedProp::kNone, 0, 0.9f);
      walker(room_loop, 0.5f, CarriedProp::kNone, 1, 0.9f);
      break;
    case Cast::kTourWalkers:
      // Three people round the room, one against the others' direction: the touring camera
      // meets people coming towards it and crossing its view, lap after lap.
      walker(room_loop, 0.0f, CarriedProp::kNone, 0, 0.9f);
      walker({room_loop.rbegin(), room_loop.rend()}, 0.3f, CarriedProp::kNone, 1, 0.8f);
      walker(room_loop, 0.6f, CarriedProp::kNone, 2, 1.0f);
      break;
  }
  return script;
}

}  // namespace lrd::synth
