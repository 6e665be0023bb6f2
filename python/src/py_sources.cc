// lrdslam.io.read_sequence and lrdslam.synth.render: recorded and rendered frames as numpy arrays.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>

#include "lrd/runner/sequence_runner.h"
#include "lrd/synth/presets.h"
#include "lrd/synth/realism.h"
#include "lrd/synth/synthetic_source.h"
#include "lrd/util/error.h"
#include "numpy_mat.h"
#include "py_common.h"

namespace lrd::python {

namespace {

namespace fs = std::filesystem;
using py::literals::operator""_a;

// One decoded frame: colour in RGB order (numpy's convention; track_rgbd's default), depth in
// metres (0: no measurement).
struct Frame {
  std::size_t index = 0;
  double timestamp = 0.0, depth_timestamp = 0.0;
  std::string rgb_path, depth_path;
  cv::Mat rgb, depth;
};

Frame load_frame(const Sequence& s, py::ssize_t i) {
  const auto n = static_cast<py::ssize_t>(s.source->size());
  if (i < 0) i += n;
  if (i < 0 || i >= n) throw py::index_error("frame index out of range");
  const auto k = static_cast<std::size_t>(i);
  Frame f;
  const io::FrameEntry& e = s.source->entry(k);
  f.index = k;
  f.timestamp = e.timestamp;
  f.depth_timestamp = e.depth_timestamp;
  f.rgb_path = e.rgb_path.string();
  f.depth_path = e.depth_path.string();
  py::gil_scoped_release release;  // decoding or rendering: milliseconds
  io::RgbdFrame decoded = s.source->load_rgbd(k, s.depth_factor);
  cv::cvtColor(decoded.rgb, f.rgb, cv::COLOR_BGR2RGB);
  f.depth = std::move(decoded.depth);
  return f;
}

py::object camera_of(const io::FrameSource& source) {
  const std::optional<io::SourceCamera> c = source.camera();
  if (!c) return py::none();
  return py::dict("width"_a = c->width, "height"_a = c->height, "fx"_a = c->fx, "fy"_a = c->fy,
                  "cx"_a = c->cx, "cy"_a = c->cy,
                  "distortion"_a = std::vector<double>{c->k1, c->k2, c->p1, c->p2, c->k3},
                  "origin"_a = c->origin);
}

Sequence make_sequence(std::shared_ptr<const io::FrameSource> source, std::optional<double> depth_factor) {
  Sequence s;
  s.source = std::move(source);
  if (depth_factor) {
    if (!(*depth_factor > 0.0)) throw Error("read_sequence: depth_factor must be positive");
    s.depth_factor = *depth_factor;
  } else {
    // The unit `lrdslam run` reads the depth PNGs with: its camera's depth_map_factor.
    runner::RunOptions o;
    o.source = s.source;
    s.depth_factor = runner::resolve_config(o).camera.depth_map_factor;
  }
  return s;
}

void bind_sequence(py::module_& io) {
  py::class_<Frame>(io, "Frame", "One RGB-D frame: rgb (HxWx3 uint8, RGB order), depth (HxW float32, metres)")
      .def_readonly("index", &Frame::index)
      .def_readonly("timestamp", &Frame::timestamp)
      .def_readonly("depth_timestamp", &Frame::depth_timestamp)
      .def_readonly("rgb_path", &Frame::rgb_path)
      .def_readonly("depth_path", &Frame::depth_path)
      .def_property_readonly("rgb", [](const Frame& f) { return mat_view(f.rgb); })
      .def_property_readonly("depth", [](const Frame& f) { return mat_view(f.depth); });
  py::class_<Sequence>(io, "Sequence", "Frames decoded (or rendered) on demand: len(), seq[i], iteration")
      .def("__len__", [](const Sequence& s) { return s.source->size(); })
      .def("__getitem__", &load_frame, "index"_a)
      .def_property_readonly("path", [](const Sequence& s) { return s.source->path().string(); })
      .def_property_readonly("depth_factor", [](const Sequence& s) { return s.depth_factor; })
      .def_property_readonly("synthetic", [](const Sequence& s) { return s.source->synthetic_benchmark(); })
      .def_property_readonly("camera", [](const Sequence& s) { return camera_of(*s.source); })
      .def_property_readonly("timestamps",
                             [](const Sequence& s) {
                               py::array_t<double> t(static_cast<py::ssize_t>(s.source->size()));
                               for (std::size_t i = 0; i < s.source->size(); ++i)
                                 t.mutable_at(static_cast<py::ssize_t>(i)) = s.source->entry(i).timestamp;
                               return t;
                             })
      .def_property_readonly("ground_truth",
                             [](const Sequence& s) {
                               const std::optional<io::Trajectory> gt = s.source->ground_truth();
                               return gt ? py::object(trajectory_array(*gt)) : py::object(py::none());
                             })
      .def("__repr__", [](const Sequence& s) {
        return "<lrdslam.io.Sequence " + s.source->path().string() + ", " + std::to_string(s.source->size()) +
               " frames>";
      });
  io.def(
      "read_sequence",
      [](const fs::path& path, std::optional<std::string> rgb_topic, std::optional<std::string> depth_topic,
         std::optional<std::string> camera_info_topic, std::optional<std::string> gt_from_tf,
         std::optional<double> depth_factor) {
        app::BagCli bag;
        if (rgb_topic) bag.rgb_topic = *rgb_topic;
        if (depth_topic) bag.depth_topic = *depth_topic;
        if (camera_info_topic) bag.camera_info_topic = *camera_info_topic;
        if (gt_from_tf) bag.gt_from_tf = *gt_from_tf;
        return make_sequence(open_source(path, bag), depth_factor);
      },
      "path"_a, py::kw_only(), "rgb_topic"_a = py::none(), "depth_topic"_a = py::none(),
      "camera_info_topic"_a = py::none(), "gt_from_tf"_a = py::none(), "depth_factor"_a = py::none(),
      "A TUM-layout folder or a bag, as `lrdslam run` reads it");
}

void bind_render(py::module_& synth) {
  synth.def("presets", [] {
    std::vector<std::string> names;
    for (const synth::PresetSpec& p : synth::preset_specs()) names.push_back(p.name);
    return names;
  });
  synth.def(
      "render",
      [](const std::string& preset, std::uint64_t seed, std::optional<int> frames, int session,
         const std::string& realism, std::optional<std::string> realism_off, double camera_speed,
         bool motion_blur) {
        synth::SynthOptions o;
        o.preset = preset;
        o.seed = seed;
        o.frames = frames.value_or(-1);
        o.session = session;
        o.camera_speed = camera_speed;
        o.motion_blur = motion_blur;
        if (realism != "clean" && realism != "tum")
          throw Error("render: realism must be 'clean' or 'tum', got '" + realism + "'");
        o.realism = synth::realism_profile(realism);
        if (realism_off) synth::disable_realism_effects(o.realism, *realism_off);
        std::shared_ptr<const io::FrameSource> source;
        {
          py::gil_scoped_release release;  // the scene and its textures: about a second
          source = std::make_shared<const synth::SyntheticSource>(o);
        }
        return make_sequence(std::move(source), std::nullopt);
      },
      "preset"_a, py::kw_only(), "seed"_a = 1, "frames"_a = py::none(), "session"_a = 1,
      "realism"_a = "clean", "realism_off"_a = py::none(), "camera_speed"_a = 1.0, "motion_blur"_a = false,
      "The frames `lrdslam synth` writes for this preset, rendered on demand");
}

}  // namespace

void bind_sources(py::module_& io, py::module_& synth) {
  bind_sequence(io);
  bind_render(synth);
}

}  // namespace lrd::python
