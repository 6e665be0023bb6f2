// Configure: which camera, config and segmenter a run gets, read once into SystemParams.
#include <fmt/format.h>

#include <filesystem>

#include "lrd/config/orbslam_settings.h"
#include "lrd/runner/sequence_runner.h"
#include "lrd/segmentation/onnx_presets.h"
#include "lrd/util/error.h"

namespace lrd::runner {

namespace fs = std::filesystem;

camera::PinholeCamera camera_from_source(const io::SourceCamera& s, camera::PinholeCamera c) {
  c.name = "camera_info";
  c.width = s.width;
  c.height = s.height;
  c.fx = s.fx;
  c.fy = s.fy;
  c.cx = s.cx;
  c.cy = s.cy;
  c.distortion = {s.k1, s.k2, s.p1, s.p2, s.k3};
  c.readout_time = s.readout_time;
  return c;
}

fs::path data_folder(const RunOptions& o) {
  if (o.source) return o.source->folder().value_or(fs::path{});
  return o.sequence;
}

namespace {

// The file or folder name a dataset gave a sequence.
std::string dataset_name_of(const fs::path& named) {
  if (named.empty()) return {};
  std::string name = fs::absolute(named).lexically_normal().filename().string();
  if (name.empty()) name = fs::absolute(named).lexically_normal().parent_path().filename().string();
  return name;
}

// TUM folder and bag names carry the sensor: rgbd_dataset_freiburg3_walking_xyz(.bag) -> '3'.
char tum_sensor_of(const std::string& name) {
  const std::size_t at = name.find("freiburg");
  const char sensor = at != std::string::npos && at + 8 < name.size() ? name[at + 8] : '\0';
  return sensor >= '1' && sensor <= '3' ? sensor : '\0';
}

// Bonn RGB-D Dynamic's folders are all named rgbd_bonn_<sequence> (one camera for all of them).
bool is_bonn_name(const std::string& name) {
  return name.starts_with("rgbd_bonn_");
}

}  // namespace

config::Config resolve_config(const RunOptions& o, std::string* source) {
  return resolve_config(o, o.config ? config::load_config(*o.config) : config::Config{}, source);
}

config::Config resolve_config(const RunOptions& o, config::Config cfg, std::string* source) {
  std::string from;
  const std::string dataset_name = dataset_name_of(o.source ? o.source->path() : o.sequence);
  const char sensor = tum_sensor_of(dataset_name);
  const auto carried = o.source ? o.source->camera() : std::nullopt;
  const fs::path folder = data_folder(o);
  if (o.settings && o.preset) throw Error("--settings and --preset cannot be combined");
  if (o.settings) {
    const config::Settings s = config::read_orbslam_settings(*o.settings);
    cfg.camera = s.camera;
    cfg.features = s.orb;
    from = "settings " + o.settings->string();
  } else if (o.preset) {
    cfg.camera = camera::camera_preset(*o.preset);
    from = "preset " + *o.preset;
  } else if (cfg.camera_given) {
    from = "config " + cfg.file.string();
  } else if (carried && sensor != '\0') {
    // TUM's bags carry the driver's default camera_info (fx 525), not TUM's calibration: the
    // sensor's preset makes a bag run match the folder run and the published results.
    cfg.camera = camera::camera_preset(fmt::format("tum{}", sensor));
    from = fmt::format("preset tum{} (from the bag name; TUM's camera_info is the driver's default)", sensor);
  } else if (carried) {
    cfg.camera = camera_from_source(*carried, cfg.camera);
    from = carried->origin;
  } else if (!folder.empty() && fs::exists(folder / "settings.yaml")) {
    const config::Settings s = config::read_orbslam_settings(folder / "settings.yaml");
    cfg.camera = s.camera;
    from = "settings " + (folder / "settings.yaml").string();
  } else if (sensor != '\0') {
    // fmt, not string concatenation: gcc 12 -O1 under TSan warns of a false array-bounds overflow.
    cfg.camera = camera::camera_preset(fmt::format("tum{}", sensor));
    from = fmt::format("preset tum{} (from the folder name)", sensor);
  } else if (!folder.empty() && is_bonn_name(dataset_name)) {
    cfg.camera = camera::camera_preset("bonn");
    from = "preset bonn (from the folder name)";
  } else {
    from = "preset tum3 (default)";
  }
  if (source != nullptr) *source = from;
  return cfg;
}

segmentation::SegmentationParams segmenter_preset(const std::string& name, const fs::path& sequence,
                                                  segmentation::SegmentationParams p, const fs::path& model) {
  using segmentation::Backend;
  if (name == "none") {
    p.backend = Backend::None;
  } else if (name == "gt-masks" || name == "gt-masks-all") {
    if (sequence.empty())
      throw Error("--segmenter " + name +
                  " reads the synthetic sequence folder's mask/; this source has none");
    p.backend = Backend::Masks;
    p.masks.folder = sequence / "mask";
    // Synthetic mask values: 1 person, 2 moved object, 3 balloon (sequence.json "mask_values").
    p.masks.dynamic_values = name == "gt-masks" ? std::vector<int>{1} : std::vector<int>{1, 2, 3};
  } else if (segmentation::is_onnx_preset(name)) {
    p.backend = Backend::Onnx;
    p.onnx = segmentation::onnx_preset(name, model);
  } else {
    throw Error("unknown segmenter '" + name +
                "' (choose none, gt-masks, gt-masks-all, fnet, selfie, selfie-landscape or espnetv2-voc)");
  }
  return p;
}

std::string default_segmenter(const fs::path& sequence) {
  // Our synthetic benchmark writes sequence.json; FNet-lite was trained on its renders. Real
  // camera data gets the network that knows real people.
  return !sequence.empty() && fs::exists(sequence / "sequence.json") ? "fnet" : "selfie-landscape";
}

SystemParams configure_system(const RunOptions& o, const config::Config& cfg) {
  SystemOptions sopts;
  sopts.deterministic = o.deterministic;
  if (o.mode) sopts.mode = dynamic::parse_mode(*o.mode);
  if (o.dense || o.save_repaired) sopts.dense = true;
  sopts.occupancy = o.occupancy;
  if (o.no_loop_closing) sopts.loop_closing = false;
  if (o.vocabulary) sopts.vocabulary = *o.vocabulary;
  SystemParams p = SystemParams::from_config(cfg, sopts);
  // A mode that needs masks with no segmenter configured gets the default network for the data.
  std::optional<std::string> name = o.segmenter;
  if (!name && dynamic::uses_segmentation(p.dynamic.mode) &&
      p.segmentation.backend == segmentation::Backend::None)
    name = o.source && o.source->synthetic_benchmark() ? "fnet" : default_segmenter(data_folder(o));
  if (name)
    p.segmentation =
        segmenter_preset(*name, data_folder(o), p.segmentation, o.segmenter_model.value_or(fs::path{}));
  return p;
}

}  // namespace lrd::runner
