#include "lrd/dense/dense_params.h"

namespace lrd::dense {

DenseParams DenseParams::from_config(config::NodeReader r) {
  DenseParams p;
  p.enabled = r.get("enabled", p.enabled);
  p.voxel_size = r.get("voxel_size", p.voxel_size);
  r.check(p.voxel_size >= 0.001 && p.voxel_size <= 1.0, "voxel_size", "must be in [0.001, 1] m");
  p.max_depth = r.get("max_depth", p.max_depth);
  r.check(p.max_depth > 0, "max_depth", "must be > 0");
  p.pixel_stride = r.get("pixel_stride", p.pixel_stride);
  r.check(p.pixel_stride >= 1 && p.pixel_stride <= 16, "pixel_stride", "must be in [1, 16]");
  p.depth_edge = r.get("depth_edge", p.depth_edge);
  r.check(p.depth_edge > 0, "depth_edge", "must be > 0");
  p.mask_margin_px = r.get("mask_margin_px", p.mask_margin_px);
  r.check(p.mask_margin_px >= 0 && p.mask_margin_px <= 200, "mask_margin_px", "must be in [0, 200]");
  p.edge_margin_px = r.get("edge_margin_px", p.edge_margin_px);
  r.check(p.edge_margin_px >= 0 && p.edge_margin_px <= 200, "edge_margin_px", "must be in [0, 200]");
  p.max_memory_mb = r.get("max_memory_mb", p.max_memory_mb);
  r.check(p.max_memory_mb >= 0, "max_memory_mb", "must be >= 0 (0: no cap)");
  config::NodeReader q = r.section("repair");
  p.repair.enabled = q.get("enabled", p.repair.enabled);
  p.repair.keyframes = q.get("keyframes", p.repair.keyframes);
  q.check(p.repair.keyframes >= 1 && p.repair.keyframes <= 100, "keyframes", "must be in [1, 100]");
  p.repair.max_depth = q.get("max_depth", p.repair.max_depth);
  q.check(p.repair.max_depth > 0, "max_depth", "must be > 0");
  p.repair.depth_edge = q.get("depth_edge", p.repair.depth_edge);
  q.check(p.repair.depth_edge > 0, "depth_edge", "must be > 0");
  p.repair.pixel_stride = q.get("pixel_stride", p.repair.pixel_stride);
  q.check(p.repair.pixel_stride >= 1 && p.repair.pixel_stride <= 4, "pixel_stride", "must be in [1, 4]");
  p.repair.surface_band = q.get("surface_band", p.repair.surface_band);
  q.check(p.repair.surface_band >= 0 && p.repair.surface_band < 0.5, "surface_band", "must be in [0, 0.5)");
  q.finish();
  config::NodeReader f = r.section("free_space");
  p.free_space.keyframes = f.get("keyframes", p.free_space.keyframes);
  f.check(p.free_space.keyframes >= 1 && p.free_space.keyframes <= 200, "keyframes", "must be in [1, 200]");
  p.free_space.step = f.get("step", p.free_space.step);
  f.check(p.free_space.step >= 1 && p.free_space.step <= 20, "step", "must be in [1, 20]");
  p.free_space.votes = f.get("votes", p.free_space.votes);
  f.check(p.free_space.votes >= 0 && p.free_space.votes <= 20, "votes", "must be in [0, 20]");
  p.free_space.margin = f.get("margin", p.free_space.margin);
  f.check(p.free_space.margin >= 0, "margin", "must be >= 0");
  p.free_space.margin_ratio = f.get("margin_ratio", p.free_space.margin_ratio);
  f.check(p.free_space.margin_ratio >= 0, "margin_ratio", "must be >= 0");
  f.finish();
  r.finish();
  return p;
}

}  // namespace lrd::dense
