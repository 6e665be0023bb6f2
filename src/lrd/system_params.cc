#include "lrd/system_params.h"

namespace lrd {

SystemParams SystemParams::from_config(const config::Config& cfg, const SystemOptions& o) {
  const std::filesystem::path base = cfg.file.empty() ? std::filesystem::path{} : cfg.file.parent_path();
  SystemParams p;
  p.tracking = tracking::TrackerParams::from_config(cfg.tracking);
  p.mapping = mapping::LocalMapperParams::from_config(cfg.mapping);
  p.dynamic = dynamic::DynamicParams::from_config(cfg.dynamic);
  p.segmentation = o.segmentation ? *o.segmentation
                                  : segmentation::SegmentationParams::from_config(cfg.segmentation, base);
  p.loop_closing = loop::LoopClosingParams::from_config(cfg.loop_closing, base);
  p.dense = dense::DenseParams::from_config(cfg.dense);
  p.occupancy = occupancy::OccupancyParams::from_config(cfg.occupancy);
  if (o.mode) p.dynamic.mode = *o.mode;
  if (o.deterministic) p.segmentation.schedule = segmentation::Schedule::Sync;
  if (o.dense) p.dense.enabled = *o.dense;
  if (o.occupancy) p.occupancy.enabled = *o.occupancy;
  if (o.occupancy.value_or(false)) p.dense.enabled = true;
  if (o.loop_closing) p.loop_closing.enabled = *o.loop_closing;
  if (o.vocabulary) p.loop_closing.vocabulary = *o.vocabulary;
  return p;
}

}  // namespace lrd
