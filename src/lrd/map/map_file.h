#pragma once
// Map files (.lrdmap, docs/map-files.md): a run's sparse map, to localize in or extend later.
//
// Layout, little-endian: "LRDMAP01", u32 version, u32 section count, u64 file size; then the
// sections, each a 4-character tag, a u64 payload length and the payload; last, a u64 FNV-1a 64
// of every byte before it. Sections (readers skip tags they do not know):
//   CAMR  the camera (size, intrinsics, distortion, bf, ThDepth, depth factor)
//   VOCB  the vocabulary's fingerprint (place::Vocabulary::fingerprint) and word count: bag-of-
//         words vectors are not stored, they are recomputed on load with the same vocabulary
//   KFRM  keyframes in id order: id, frame id, time, T_cw, pyramid scales, image bounds, every
//         keypoint (as detected and undistorted, descriptor, depth, virtual right coordinate, map
//         point id), then covisibility edges, the ordered covisibles, spanning-tree parent, loop
//         edges and the culling guard
//   MPNT  map points in id order: id, first keyframe and frame, reference keyframe, position,
//         mean viewing direction, descriptor, scale-invariance distances, visible/found counts,
//         observations (keyframe id, keypoint index)
//   NXID  the next keyframe and map point ids
// A map saved, loaded and saved again gives the same bytes.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/map/map.h"

namespace lrd::map {

inline constexpr std::uint32_t kMapFileVersion = 1;

// What a map was made with, beyond the map itself.
struct MapFileHeader {
  camera::PinholeCamera camera;
  std::uint64_t vocabulary_fingerprint = 0;
  std::uint64_t vocabulary_words = 0;
};

// A keyframe as capture_map() copied it: what can still change, and the keyframe itself for its
// features, which never change once it exists.
struct CapturedKeyFrame {
  const KeyFrame* keyframe = nullptr;
  Eigen::Isometry3d T_cw = Eigen::Isometry3d::Identity();
  std::vector<std::uint64_t> point_ids;  // per keypoint, the map point it observes (or none)
  std::string graph;                     // covisibility, spanning tree, loop edges, flags: as saved
};

// A map file in two steps, so that a save holds the map mutex only for what can change while it
// runs: capture_map() under map.mutex() copies poses, matches, graphs and map points (a few
// milliseconds for a room's map); serialize_capture() without the mutex reads the keyframes'
// features and builds the bytes. The keyframes must live until then: the caller is a
// reclamation participant that has not declared since the capture, or the map does not change.
struct MapCapture {
  MapFileHeader header;
  std::vector<CapturedKeyFrame> keyframes;
  std::string points;  // the MPNT section's payload
  std::uint64_t next_keyframe_id = 0, next_map_point_id = 0;
};
[[nodiscard]] MapCapture capture_map(const Map& map, const MapFileHeader& header);
[[nodiscard]] std::string serialize_capture(const MapCapture& capture);
// The file's bytes for the map's active keyframes and points, in one step. Call under map.mutex().
[[nodiscard]] std::string serialize_map(const Map& map, const MapFileHeader& header);
// Writes serialize_map() to `file` (whole or not at all); throws lrd::Error naming the file.
void save_map_file(const std::filesystem::path& file, const Map& map, const MapFileHeader& header);

// What the run loading a map uses: the map must have been made with the same camera and vocabulary,
// and its keyframes get this camera (the file keeps the calibration, not every sensor setting).
struct MapFileExpectation {
  camera::PinholeCamera camera;
  std::uint64_t vocabulary_fingerprint = 0;
};

// Reads `file` into `map`, which must be empty, and returns what it was made with. Throws one
// lrd::Error line naming the file: missing, not a map file, another version, truncated, checksum
// mismatch (corrupted), inconsistent (an id named but not held, an index out of range, a point
// and a keyframe that disagree on their observation, a spanning tree that is not a tree, a
// one-sided loop edge), without keyframes, or (with `expect`) made with another camera or
// vocabulary — checked before any keyframe is read. The keyframes' bag-of-words vectors are left
// to the caller (they need the vocabulary).
MapFileHeader load_map_file(const std::filesystem::path& file, Map& map,
                            const std::optional<MapFileExpectation>& expect = std::nullopt);

// Throws "FILE: ..." when the map was made with another vocabulary or another camera than the
// ones given (intrinsics and ThDepth within 1e-6 relative, same image size and distortion).
void check_map_matches(const std::filesystem::path& file, const MapFileHeader& saved,
                       const camera::PinholeCamera& camera, std::uint64_t vocabulary_fingerprint);

}  // namespace lrd::map
