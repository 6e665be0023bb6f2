// load_map_file and check_map_matches (map/map_file.h): reading a .lrdmap back.
#include <cmath>
#include <cstring>
#include <map>
#include <unordered_map>
#include <vector>

#include "lrd/map/map_file.h"
#include "lrd/map/map_file_format.h"
#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"

namespace lrd::map {

namespace {

using file_format::kHeaderBytes;
using file_format::kMagic;
using file_format::kNone;
// The fewest bytes a keypoint, an edge, an observation take: counts beyond what the section can
// hold are corrupt, not allocations to attempt.
constexpr std::size_t kKeypointBytes = 5 * 4 + 2 * 4 + 4 * 4 + 32 + 8;

struct PendingKeyFrame {
  KeyFrame* keyframe;
  std::vector<std::uint64_t> slots;  // map point id per keypoint
  std::vector<std::pair<std::uint64_t, int>> connections, ordered;
  std::uint64_t parent;
  std::vector<std::uint64_t> loop_edges;
  std::uint32_t flags;  // 1: not_erase, 2: first_connection
};

struct PendingPoint {
  MapPoint* point;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> observations;
};

std::uint64_t count(util::ByteReader& in, std::size_t record_bytes, const char* what) {
  const std::uint64_t n = in.u64(what);
  if (record_bytes > 0 && n > in.remaining() / record_bytes)
    throw file_error(in.file(), std::string("corrupt: ") + std::to_string(n) + " " + what +
                                    " cannot fit in " + std::to_string(in.remaining()) + " bytes");
  return n;
}

std::uint32_t count32(util::ByteReader& in, std::size_t record_bytes, const char* what) {
  const std::uint32_t n = in.u32(what);
  if (record_bytes > 0 && n > in.remaining() / record_bytes)
    throw file_error(in.file(), std::string("corrupt: ") + std::to_string(n) + " " + what +
                                    " cannot fit in " + std::to_string(in.remaining()) + " bytes");
  return n;
}

Eigen::Isometry3d read_pose(util::ByteReader& in) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) T.matrix()(r, c) = in.f64("keyframe pose");
  return T;
}

camera::PinholeCamera read_camera(util::ByteReader& in) {
  camera::PinholeCamera cam;
  cam.name = "map";
  cam.width = in.i32("camera");
  cam.height = in.i32("camera");
  for (double* v :
       {&cam.fx, &cam.fy, &cam.cx, &cam.cy, &cam.distortion.k1, &cam.distortion.k2, &cam.distortion.p1,
        &cam.distortion.p2, &cam.distortion.k3, &cam.bf, &cam.th_depth, &cam.depth_map_factor})
    *v = in.f64("camera");
  if (cam.width <= 0 || cam.height <= 0 || !(cam.fx > 0) || !(cam.fy > 0))
    throw file_error(in.file(), "corrupt camera section: non-positive image size or focal length");
  return cam;
}

data::Frame::SavedFeatures read_features(util::ByteReader& in, std::vector<std::uint64_t>& slots) {
  data::Frame::SavedFeatures f;
  const std::uint32_t levels = count32(in, 12, "pyramid levels");
  for (std::uint32_t l = 0; l < levels; ++l) {
    f.scale_factors.push_back(in.f32("pyramid scales"));
    f.level_sigma2.push_back(in.f32("pyramid scales"));
    f.inv_level_sigma2.push_back(in.f32("pyramid scales"));
  }
  f.bounds.x = in.f32("image bounds");
  f.bounds.y = in.f32("image bounds");
  f.bounds.width = in.f32("image bounds");
  f.bounds.height = in.f32("image bounds");
  const std::uint32_t n = count32(in, kKeypointBytes, "keypoints");
  f.descriptors = cv::Mat(static_cast<int>(n), 32, CV_8U);
  for (std::uint32_t i = 0; i < n; ++i) {
    cv::KeyPoint kp;
    kp.pt.x = in.f32("keypoint");
    kp.pt.y = in.f32("keypoint");
    kp.size = in.f32("keypoint");
    kp.angle = in.f32("keypoint");
    kp.response = in.f32("keypoint");
    kp.octave = in.i32("keypoint");
    kp.class_id = in.i32("keypoint");
    f.keypoints.push_back(kp);
    kp.pt.x = in.f32("keypoint");
    kp.pt.y = in.f32("keypoint");
    f.undistorted.push_back(kp);
    f.depth.push_back(in.f32("keypoint"));
    f.u_right.push_back(in.f32("keypoint"));
    std::memcpy(f.descriptors.ptr(static_cast<int>(i)), in.take(32, "descriptor").data(), 32);
    slots.push_back(in.u64("keypoint"));
    const cv::Point2f &a = f.keypoints.back().pt, &b = f.undistorted.back().pt;
    if (!std::isfinite(a.x) || !std::isfinite(a.y) || !std::isfinite(b.x) || !std::isfinite(b.y) ||
        !std::isfinite(f.depth.back()) || !std::isfinite(f.u_right.back()))
      throw file_error(in.file(), "corrupt keypoint: position or depth not finite");
    if (kp.octave < 0 || static_cast<std::size_t>(kp.octave) >= f.scale_factors.size())
      throw file_error(in.file(), "corrupt keypoint: pyramid level out of range");
  }
  if (!(f.bounds.width > 0.0f && f.bounds.height > 0.0f) || !std::isfinite(f.bounds.x) ||
      !std::isfinite(f.bounds.y) || !std::isfinite(f.bounds.width) || !std::isfinite(f.bounds.height))
    throw file_error(in.file(), "corrupt keyframe: image bounds");
  return f;
}

std::vector<std::pair<std::uint64_t, int>> read_edges(util::ByteReader& in) {
  std::vector<std::pair<std::uint64_t, int>> edges(count32(in, 12, "covisibility edges"));
  for (auto& [id, weight] : edges) {
    id = in.u64("covisibility edge");
    weight = in.i32("covisibility edge");
  }
  return edges;
}

PendingKeyFrame read_keyframe(util::ByteReader& in, const camera::PinholeCamera& cam, Map& map) {
  const std::uint64_t id = in.u64("keyframe"), frame_id = in.u64("keyframe");
  const double timestamp = in.f64("keyframe");
  const Eigen::Isometry3d T_cw = read_pose(in);
  PendingKeyFrame p{};
  data::Frame::SavedFeatures features = read_features(in, p.slots);
  try {
    if (map.keyframe(id) != nullptr) throw Error("keyframe " + std::to_string(id) + " twice");
    p.keyframe = map.restore_keyframe(id, data::Frame(frame_id, timestamp, cam, std::move(features), T_cw));
  } catch (const Error& e) {
    throw file_error(in.file(), std::string("corrupt keyframe record: ") + e.what());
  }
  p.connections = read_edges(in);
  p.ordered = read_edges(in);
  p.parent = in.u64("keyframe parent");
  p.loop_edges.resize(count32(in, 8, "loop edges"));
  for (std::uint64_t& other : p.loop_edges) other = in.u64("loop edge");
  p.flags = in.u32("keyframe");
  return p;
}

PendingPoint read_map_point(util::ByteReader& in, Map& map) {
  const std::uint64_t id = in.u64("map point"), first_kf = in.u64("map point"),
                      first_frame = in.u64("map point");
  const std::uint64_t reference = in.u64("map point");
  Eigen::Vector3d position, normal;
  for (int k = 0; k < 3; ++k) position[k] = in.f64("map point");
  for (int k = 0; k < 3; ++k) normal[k] = in.f64("map point");
  MapPoint::SavedState state{first_kf, normal, {}, 0, 0, 1, 1};
  // Every matcher reads a point's descriptor: a point without one is not a point.
  if (in.u32("map point") == 0)
    throw file_error(in.file(), "map point " + std::to_string(id) + " has no descriptor");
  state.descriptor = cv::Mat(1, 32, CV_8U);
  std::memcpy(state.descriptor.ptr(), in.take(32, "map point descriptor").data(), 32);
  state.min_distance = in.f32("map point");
  state.max_distance = in.f32("map point");
  state.visible = in.i32("map point");
  state.found = in.i32("map point");
  if (!position.allFinite())
    throw file_error(in.file(), "corrupt map point " + std::to_string(id) + ": position not finite");
  KeyFrame* ref = reference == kNone ? nullptr : map.keyframe(reference);
  if (reference != kNone && ref == nullptr)
    throw file_error(in.file(), "map point " + std::to_string(id) + " names keyframe " +
                                    std::to_string(reference) + ", which the file does not hold");
  PendingPoint p{nullptr, {}};
  try {
    p.point = map.restore_map_point(id, position, ref, first_frame);
  } catch (const Error& e) {
    throw file_error(in.file(), std::string("corrupt: ") + e.what());
  }
  p.point->restore_state(state);
  p.observations.resize(count32(in, 12, "observations"));
  if (p.observations.empty())
    throw file_error(in.file(), "map point " + std::to_string(id) + " has no observations");
  for (auto& [kf, index] : p.observations) {
    kf = in.u64("observation");
    index = in.u32("observation");
  }
  return p;
}

// Every id a record names must be in the file.
KeyFrame* keyframe_named(const Map& map, std::uint64_t id, const std::filesystem::path& file,
                         const std::string& by) {
  KeyFrame* kf = map.keyframe(id);
  if (kf == nullptr)
    throw file_error(file, by + " names keyframe " + std::to_string(id) + ", which the file does not hold");
  return kf;
}

// The points' observations and the keyframes' slots must agree both ways (freeing relies on it:
// a removed point clears the slots of the keyframes it observes, a culled keyframe the
// observations of the points in its slots).
void link_points(Map& map, std::vector<PendingKeyFrame>& keyframes, const std::vector<PendingPoint>& points,
                 const std::unordered_map<std::uint64_t, MapPoint*>& point_by_id,
                 const std::filesystem::path& file) {
  for (const PendingPoint& p : points) {
    const std::string by = "map point " + std::to_string(p.point->id());
    for (const auto& [id, index] : p.observations) {
      KeyFrame* kf = keyframe_named(map, id, file, by);
      if (index >= kf->size())
        throw file_error(file, by + " names keypoint " + std::to_string(index) + " of keyframe " +
                                   std::to_string(id) + ", which has " + std::to_string(kf->size()));
      p.point->add_observation(kf, index);
    }
    if (KeyFrame* ref = p.point->reference_keyframe(); ref != nullptr && !p.point->is_in_keyframe(ref))
      throw file_error(file,
                       by + ": its reference keyframe " + std::to_string(ref->id()) + " does not observe it");
  }
  for (PendingKeyFrame& p : keyframes)
    for (std::size_t i = 0; i < p.slots.size(); ++i) {
      if (p.slots[i] == kNone) continue;
      const auto it = point_by_id.find(p.slots[i]);
      if (it == point_by_id.end() || !it->second->is_in_keyframe(p.keyframe))
        throw file_error(file,
                         "keyframe " + std::to_string(p.keyframe->id()) + " holds map point " +
                             std::to_string(p.slots[i]) + ", which " +
                             (it == point_by_id.end() ? "the file does not hold" : "does not observe it"));
      p.keyframe->add_map_point(it->second, i);
    }
  for (const PendingPoint& p : points)
    for (const auto& [kf, index] : p.point->observations())
      if (kf->map_point(index) != p.point)
        throw file_error(file, "map point " + std::to_string(p.point->id()) + " observes keypoint " +
                                   std::to_string(index) + " of keyframe " + std::to_string(kf->id()) +
                                   ", which holds another point there");
}

// Covisibility, the spanning tree (no keyframe its own ancestor) and loop edges (both ways).
void link_graphs(Map& map, std::vector<PendingKeyFrame>& keyframes, const std::filesystem::path& file) {
  for (PendingKeyFrame& p : keyframes) {
    const std::string by = "keyframe " + std::to_string(p.keyframe->id());
    KeyFrame::SavedGraph graph;
    for (const auto& [id, w] : p.connections) graph.connections.emplace(keyframe_named(map, id, file, by), w);
    for (const auto& [id, w] : p.ordered) graph.ordered.emplace_back(keyframe_named(map, id, file, by), w);
    graph.parent = p.parent == kNone ? nullptr : keyframe_named(map, p.parent, file, by);
    for (const std::uint64_t id : p.loop_edges) graph.loop_edges.insert(keyframe_named(map, id, file, by));
    // A keyframe closing a loop is never culled (its loop edge would dangle).
    graph.not_erase = (p.flags & 1u) != 0 || !graph.loop_edges.empty();
    graph.first_connection = (p.flags & 2u) != 0;
    p.keyframe->restore_graph(std::move(graph));
  }
  for (const PendingKeyFrame& p : keyframes) {
    for (const KeyFrame* other : p.keyframe->loop_edges())
      if (other->loop_edges().count(p.keyframe) == 0)
        throw file_error(file, "keyframe " + std::to_string(p.keyframe->id()) +
                                   " has a loop edge to keyframe " + std::to_string(other->id()) +
                                   " that has none back");
    std::size_t steps = 0;
    for (const KeyFrame* up = p.keyframe->parent(); up != nullptr; up = up->parent())
      if (up == p.keyframe || ++steps > keyframes.size())
        throw file_error(file, "keyframe " + std::to_string(p.keyframe->id()) +
                                   " is its own ancestor in the spanning tree");
  }
}

// The sections by tag, checked against the header's size and the checksum.
std::map<std::string, std::string_view> sections(std::string_view bytes, const std::filesystem::path& file) {
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw file_error(file, "not an lrd-slam map file (bad magic, expected \"LRDMAP01\")");
  util::ByteReader in(bytes, file);
  in.take(sizeof kMagic, "header");
  const std::uint32_t version = in.u32("header");
  if (version != kMapFileVersion)
    throw file_error(file, "unsupported map file version " + std::to_string(version) + " (this build reads " +
                               std::to_string(kMapFileVersion) + ")");
  const std::uint32_t n = in.u32("header");
  const std::uint64_t size = in.u64("header");
  if (bytes.size() < size)
    throw file_error(file, "truncated map file: " + std::to_string(bytes.size()) + " of " +
                               std::to_string(size) + " bytes");
  if (bytes.size() > size)
    throw file_error(file, std::to_string(bytes.size() - size) + " bytes after the end of the map");
  if (size < kHeaderBytes + 8)
    throw file_error(file, "corrupt header: a map file of " + std::to_string(size) + " bytes");
  const std::string_view body = bytes.substr(0, bytes.size() - 8);
  if (util::fnv1a64(body) != util::get_u64(reinterpret_cast<const std::uint8_t*>(bytes.data() + body.size())))
    throw file_error(file, "checksum mismatch: the map file is corrupted");
  util::ByteReader sec(body, file);
  sec.take(kHeaderBytes, "header");
  std::map<std::string, std::string_view> out;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::string tag(sec.take(4, "section"));
    out[tag] = sec.take(sec.u64("section"), "section");
  }
  if (sec.remaining() != 0) throw file_error(file, "corrupt: bytes after the last section");
  for (const char* tag : {"CAMR", "VOCB", "KFRM", "MPNT", "NXID"})
    if (out.count(tag) == 0) throw file_error(file, std::string("corrupt: no ") + tag + " section");
  return out;
}

void expect_end(const util::ByteReader& in, const char* tag) {
  if (in.remaining() != 0)
    throw file_error(in.file(), std::string("corrupt ") + tag + " section: " +
                                    std::to_string(in.remaining()) + " bytes after its records");
}

}  // namespace

MapFileHeader load_map_file(const std::filesystem::path& file, Map& map,
                            const std::optional<MapFileExpectation>& expect) {
  if (map.keyframe_count() != 0 || map.map_point_count() != 0)
    throw file_error(file, "a map file loads into an empty map only");
  const std::string bytes = util::read_file_bytes(file, "map");
  const std::map<std::string, std::string_view> parts = sections(bytes, file);
  MapFileHeader header;
  util::ByteReader camera_section(parts.at("CAMR"), file), vocabulary(parts.at("VOCB"), file);
  header.camera = read_camera(camera_section);
  header.vocabulary_fingerprint = vocabulary.u64("vocabulary section");
  header.vocabulary_words = vocabulary.u64("vocabulary section");
  expect_end(camera_section, "CAMR");
  expect_end(vocabulary, "VOCB");

  if (expect) check_map_matches(file, header, expect->camera, expect->vocabulary_fingerprint);
  // The run's camera, when there is one: the file keeps the calibration, not every sensor setting.
  const camera::PinholeCamera& frame_camera = expect ? expect->camera : header.camera;

  util::ByteReader kfs(parts.at("KFRM"), file), mps(parts.at("MPNT"), file), next(parts.at("NXID"), file);
  std::vector<PendingKeyFrame> keyframes;
  for (std::uint64_t n = count(kfs, 8, "keyframes"), k = 0; k < n; ++k)
    keyframes.push_back(read_keyframe(kfs, frame_camera, map));
  expect_end(kfs, "KFRM");
  if (keyframes.empty()) throw file_error(file, "the map holds no keyframes");
  std::vector<PendingPoint> points;
  std::unordered_map<std::uint64_t, MapPoint*> point_by_id;
  for (std::uint64_t n = count(mps, 8, "map points"), k = 0; k < n; ++k) {
    points.push_back(read_map_point(mps, map));
    point_by_id.emplace(points.back().point->id(), points.back().point);
  }
  expect_end(mps, "MPNT");
  link_points(map, keyframes, points, point_by_id, file);
  link_graphs(map, keyframes, file);
  const std::uint64_t next_keyframe = next.u64("NXID section"), next_point = next.u64("NXID section");
  expect_end(next, "NXID");
  map.restore_next_ids(next_keyframe, next_point);
  return header;
}

void check_map_matches(const std::filesystem::path& file, const MapFileHeader& saved,
                       const camera::PinholeCamera& camera, std::uint64_t vocabulary_fingerprint) {
  if (saved.vocabulary_fingerprint != vocabulary_fingerprint)
    throw file_error(file, "the map was made with another vocabulary (fingerprint " +
                               std::to_string(saved.vocabulary_fingerprint) + ", this run's " +
                               std::to_string(vocabulary_fingerprint) + ")");
  const camera::PinholeCamera& a = saved.camera;
  if (a.width != camera.width || a.height != camera.height)
    throw file_error(file, "the map's camera is " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                               ", this run's " + std::to_string(camera.width) + "x" +
                               std::to_string(camera.height));
  const std::pair<const char*, std::pair<double, double>> values[] = {
      {"fx", {a.fx, camera.fx}},
      {"fy", {a.fy, camera.fy}},
      {"cx", {a.cx, camera.cx}},
      {"cy", {a.cy, camera.cy}},
      {"k1", {a.distortion.k1, camera.distortion.k1}},
      {"k2", {a.distortion.k2, camera.distortion.k2}},
      {"p1", {a.distortion.p1, camera.distortion.p1}},
      {"p2", {a.distortion.p2, camera.distortion.p2}},
      {"k3", {a.distortion.k3, camera.distortion.k3}},
      {"bf", {a.bf, camera.bf}},
      {"ThDepth", {a.th_depth, camera.th_depth}}};
  for (const auto& [name, v] : values)
    if (std::abs(v.first - v.second) > 1e-6 * std::max(1.0, std::abs(v.second)))
      throw file_error(file, std::string("the map's camera differs from this run's: ") + name + " " +
                                 std::to_string(v.first) + " in the map, " + std::to_string(v.second) +
                                 " here");
}

}  // namespace lrd::map
