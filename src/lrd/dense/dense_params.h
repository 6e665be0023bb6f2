#pragma once
// The `dense` section of the config: background repair (paper §2.7, last paragraph) and the dense
// point-cloud map (Figs. 6, 18). config/default.yaml documents every key.
#include "lrd/config/node_reader.h"
#include "lrd/dense/free_space_check.h"

namespace lrd::dense {

struct RepairParams {
  bool enabled = true;
  int keyframes = 10;          // earlier keyframes whose static pixels fill a new keyframe's dynamic region
  double max_depth = 6.0;      // source pixels farther than this (m) are not used
  double depth_edge = 0.05;    // source pixels on depth edges (relative jump to a neighbour) are not used
  int pixel_stride = 2;        // every n-th source pixel in both directions, splatted over (n + 1)^2
  double surface_band = 0.03;  // samples within this share of z behind the nearest are averaged with it
};

struct DenseParams {
  bool enabled = false;      // the dense-mapping thread (lrdslam run --dense)
  double voxel_size = 0.01;  // m; one point per occupied voxel, colour and position averaged
  // m; depth beyond this stays out of the map. The sensor's noise grows with z^2: on walking_xyz
  // 4 m left 4.3 % of the points > 5 cm off the surfaces, 3.5 m 1.5 %, 3 m 0.01 % (docs/dense-map.md).
  double max_depth = 3.0;
  int pixel_stride = 2;      // every n-th pixel in both directions enters the keyframe's cloud
  double depth_edge = 0.05;  // pixels whose depth jumps by more than this share of z to a neighbour
                             // (mixed pixels at object outlines) stay out of the map
  // Pixels within this many of a dynamic one are where a mask misses a hand or a shoulder: the
  // occupancy map makes them a surface only once a second keyframe measures it too.
  int mask_margin_px = 50;
  // The same within this many of the image's edge, where a segmenter misses a person cut off by it.
  int edge_margin_px = 24;
  // MiB the stored keyframe clouds may take (16 bytes a point); 0: no cap. Over it, the clouds of
  // keyframes that keyframe culling removed go first, then the oldest; the newest
  // max(repair.keyframes, free_space.keyframes) always stay (bench/results/scale.md, "Dense map
  // memory").
  double max_memory_mb = 1024.0;
  RepairParams repair;
  // Points that later or earlier keyframes (the repair's neighbours) see through stay out.
  FreeSpaceParams free_space;

  // Reads the `dense` section (and finishes it).
  static DenseParams from_config(config::NodeReader reader);
};

}  // namespace lrd::dense
