#include "lrd/map/map_file.h"

#include <cmath>
#include <cstring>
#include <unordered_map>
#include <vector>

#include "lrd/map/map_file_format.h"
#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"

namespace lrd::map {

namespace {

using util::put_f32;
using util::put_f64;
using util::put_i32;
using util::put_u32;
using util::put_u64;

using file_format::kHeaderBytes;
using file_format::kMagic;
using file_format::kNone;

// --- writing

void put_pose(std::string& s, const Eigen::Isometry3d& T) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) put_f64(s, T.matrix()(r, c));
}

void put_camera(std::string& s, const camera::PinholeCamera& cam) {
  put_i32(s, cam.width);
  put_i32(s, cam.height);
  for (const double v :
       {cam.fx, cam.fy, cam.cx, cam.cy, cam.distortion.k1, cam.distortion.k2, cam.distortion.p1,
        cam.distortion.p2, cam.distortion.k3, cam.bf, cam.th_depth, cam.depth_map_factor})
    put_f64(s, v);
}

// What can change in a keyframe once it exists, copied under the map mutex: its pose, its matches
// and its places in the graphs. Its features never change, so they are read later, without the
// mutex (map_file.h: MapCapture).
CapturedKeyFrame capture_keyframe(KeyFrame& kf) {  // non-const: points look keyframes up by pointer
  CapturedKeyFrame c;
  c.keyframe = &kf;
  c.T_cw = kf.T_cw();
  c.point_ids.resize(kf.features().size());
  for (std::size_t i = 0; i < c.point_ids.size(); ++i) {
    // Only points that know this keyframe: a keyframe still queued for local mapping may hold
    // matches that do not (yet) observe it, and a loaded map must be consistent both ways.
    MapPoint* mp = kf.map_point(i);
    c.point_ids[i] = mp != nullptr && !mp->is_bad() && mp->is_in_keyframe(&kf) ? mp->id() : kNone;
  }
  std::string& s = c.graph;
  const auto put_edges = [&s](const auto& edges) {
    put_u32(s, static_cast<std::uint32_t>(edges.size()));
    for (const auto& [other, weight] : edges) {
      put_u64(s, other->id());
      put_i32(s, weight);
    }
  };
  put_edges(kf.connections());
  std::vector<std::pair<KeyFrame*, int>> ordered;
  for (std::size_t i = 0; i < kf.ordered_covisibles().size(); ++i)
    ordered.emplace_back(kf.ordered_covisibles()[i], kf.ordered_weights()[i]);
  put_edges(ordered);
  put_u64(s, kf.parent() != nullptr ? kf.parent()->id() : kNone);
  put_u32(s, static_cast<std::uint32_t>(kf.loop_edges().size()));
  for (const KeyFrame* other : kf.loop_edges()) put_u64(s, other->id());
  put_u32(s, (kf.not_erase() ? 1u : 0u) | (kf.first_connection() ? 2u : 0u));
  return c;
}

void put_keyframe(std::string& s, const CapturedKeyFrame& c) {
  const KeyFrame& kf = *c.keyframe;
  const data::Frame& f = kf.features();
  const data::Frame::SavedFeatures saved = f.saved_features();
  put_u64(s, kf.id());
  put_u64(s, kf.frame_id());
  put_f64(s, kf.timestamp());
  put_pose(s, c.T_cw);
  put_u32(s, static_cast<std::uint32_t>(saved.scale_factors.size()));
  for (std::size_t l = 0; l < saved.scale_factors.size(); ++l) {
    put_f32(s, saved.scale_factors[l]);
    put_f32(s, saved.level_sigma2[l]);
    put_f32(s, saved.inv_level_sigma2[l]);
  }
  for (const float v : {saved.bounds.x, saved.bounds.y, saved.bounds.width, saved.bounds.height})
    put_f32(s, v);
  put_u32(s, static_cast<std::uint32_t>(f.size()));
  for (std::size_t i = 0; i < f.size(); ++i) {
    const cv::KeyPoint& kp = saved.keypoints[i];
    for (const float v : {kp.pt.x, kp.pt.y, kp.size, kp.angle, kp.response}) put_f32(s, v);
    put_i32(s, kp.octave);
    put_i32(s, kp.class_id);
    put_f32(s, saved.undistorted[i].pt.x);
    put_f32(s, saved.undistorted[i].pt.y);
    put_f32(s, saved.depth[i]);
    put_f32(s, saved.u_right[i]);
    s.append(reinterpret_cast<const char*>(saved.descriptors.ptr(static_cast<int>(i))), 32);
    put_u64(s, c.point_ids[i]);
  }
  s += c.graph;
}

void put_map_point(std::string& s, const MapPoint& mp) {
  put_u64(s, mp.id());
  put_u64(s, mp.first_keyframe_id());
  put_u64(s, mp.first_frame_id());
  KeyFrame* ref = mp.reference_keyframe();
  put_u64(s, ref != nullptr && !ref->is_bad() && mp.is_in_keyframe(ref) ? ref->id() : kNone);
  for (int k = 0; k < 3; ++k) put_f64(s, mp.position()[k]);
  for (int k = 0; k < 3; ++k) put_f64(s, mp.normal()[k]);
  const bool has_descriptor = !mp.descriptor().empty();
  put_u32(s, has_descriptor ? 1 : 0);
  if (has_descriptor) s.append(reinterpret_cast<const char*>(mp.descriptor().ptr()), 32);
  put_f32(s, mp.min_distance());
  put_f32(s, mp.max_distance());
  put_i32(s, mp.visible());
  put_i32(s, mp.found());
  std::vector<std::pair<std::uint64_t, std::size_t>> observations;
  for (const auto& [kf, index] : mp.observations())
    if (!kf->is_bad()) observations.emplace_back(kf->id(), index);
  put_u32(s, static_cast<std::uint32_t>(observations.size()));
  for (const auto& [id, index] : observations) {
    put_u64(s, id);
    put_u32(s, static_cast<std::uint32_t>(index));
  }
}

void put_section(std::string& file, const char (&tag)[5], const std::string& payload) {
  file.append(tag, 4);
  put_u64(file, payload.size());
  file += payload;
}

}  // namespace

MapCapture capture_map(const Map& map, const MapFileHeader& header) {
  MapCapture c;
  c.header = header;
  for (KeyFrame* kf : map.keyframes()) c.keyframes.push_back(capture_keyframe(*kf));
  const std::vector<MapPoint*> mps = map.map_points();
  put_u64(c.points, mps.size());
  for (const MapPoint* mp : mps) put_map_point(c.points, *mp);
  c.next_keyframe_id = map.next_keyframe_id();
  c.next_map_point_id = map.next_map_point_id();
  return c;
}

std::string serialize_capture(const MapCapture& c) {
  std::string camera, vocabulary, keyframes, next_ids;
  put_camera(camera, c.header.camera);
  put_u64(vocabulary, c.header.vocabulary_fingerprint);
  put_u64(vocabulary, c.header.vocabulary_words);
  put_u64(keyframes, c.keyframes.size());
  for (const CapturedKeyFrame& kf : c.keyframes) put_keyframe(keyframes, kf);
  put_u64(next_ids, c.next_keyframe_id);
  put_u64(next_ids, c.next_map_point_id);

  std::string out(kMagic, sizeof kMagic);
  put_u32(out, kMapFileVersion);
  put_u32(out, 5);
  const std::size_t size = kHeaderBytes + 5 * 12 + camera.size() + vocabulary.size() + keyframes.size() +
                           c.points.size() + next_ids.size() + 8;
  put_u64(out, size);
  out.reserve(size);
  put_section(out, "CAMR", camera);
  put_section(out, "VOCB", vocabulary);
  put_section(out, "KFRM", keyframes);
  put_section(out, "MPNT", c.points);
  put_section(out, "NXID", next_ids);
  put_u64(out, util::fnv1a64(out));
  return out;
}

std::string serialize_map(const Map& map, const MapFileHeader& header) {
  return serialize_capture(capture_map(map, header));
}

void save_map_file(const std::filesystem::path& file, const Map& map, const MapFileHeader& header) {
  util::write_file_bytes(file, serialize_map(map, header));
}

}  // namespace lrd::map
