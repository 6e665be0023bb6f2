// lrdslam.System: lrd::System for Python, configured exactly as `lrdslam run` configures it.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <utility>

#include "lrd/runner/sequence_runner.h"
#include "lrd/system.h"
#include "lrd/util/error.h"
#include "numpy_mat.h"
#include "py_common.h"
#include "py_events.h"

namespace lrd::python {

namespace {

namespace fs = std::filesystem;
using py::literals::operator""_a;

struct SystemArgs {
  py::object config, sequence;
  std::optional<fs::path> settings;
  std::optional<std::string> preset, mode, segmenter;
  std::optional<fs::path> segmenter_model;
  bool dense = false;
  std::optional<bool> occupancy;
  bool deterministic = false, loop_closing = true;
  std::optional<fs::path> vocabulary;
  bool localization_only = false, yardstick = false;
};

// config=None: the built-in defaults; a path: that YAML file; a dict: the same sections as a file.
config::Config read_config(const py::object& config) {
  if (config.is_none()) return config::Config{};
  if (py::isinstance<py::dict>(config)) {
    const auto text = py::module_::import("yaml").attr("safe_dump")(config, "default_flow_style"_a = false);
    return config::load_config_text(text.cast<std::string>(), "config dict");
  }
  return config::load_config(config.cast<fs::path>());
}

class PySystem {
 public:
  explicit PySystem(const SystemArgs& a) {
    runner::RunOptions o;
    if (py::isinstance<Sequence>(a.sequence)) {
      o.source = a.sequence.cast<const Sequence&>().source;
    } else if (!a.sequence.is_none()) {
      o.sequence = a.sequence.cast<fs::path>();
      o.source = open_source(o.sequence, app::BagCli{});
    }
    o.settings = a.settings;
    o.preset = a.preset;
    o.deterministic = a.deterministic;
    o.mode = a.mode;
    o.segmenter = a.segmenter;
    o.segmenter_model = a.segmenter_model;
    o.dense = a.dense;
    o.occupancy = a.occupancy;
    o.no_loop_closing = !a.loop_closing;
    o.vocabulary = a.vocabulary;
    const config::Config cfg = runner::resolve_config(o, read_config(a.config), &camera_source_);
    const SystemParams params = runner::configure_system(o, cfg);
    SystemOptions sopts;
    sopts.deterministic = a.deterministic;
    sopts.localization_only = a.localization_only;
    sopts.yardstick = a.yardstick;
    py::gil_scoped_release release;  // the vocabulary loads for a second or two
    system_ = std::make_unique<System>(cfg, params, sopts);
  }
  ~PySystem() {
    // Its threads deliver events to Python callbacks until they stop: they need the GIL.
    py::gil_scoped_release release;
    system_.reset();
  }
  PySystem(const PySystem&) = delete;
  PySystem& operator=(const PySystem&) = delete;

  TrackResult track(const py::handle& rgb, const py::handle& depth, double timestamp,
                    const std::string& order, const py::object& mask) {
    if (order != "rgb" && order != "bgr")
      throw Error("track_rgbd: order must be 'rgb' or 'bgr', got '" + order + "'");
    const ImageView colour = image_view<std::uint8_t>(rgb, "track_rgbd: rgb", kOneChannel | kThreeChannels);
    const ImageView range = depth_view(depth);
    cv::Mat image = colour.mat;
    // The system takes the camera's colour order (Camera.RGB); a mismatch costs one conversion.
    if (image.channels() == 3 && (order == "rgb") != system_->config().camera.rgb_order)
      cv::cvtColor(colour.mat, image, cv::COLOR_RGB2BGR);
    cv::Mat dynamic;
    if (!mask.is_none())
      dynamic = image_view<std::uint8_t>(mask, "track_rgbd: mask", kOneChannel).mat.clone();
    py::gil_scoped_release release;
    return system_->track_rgbd(image, range.mat, timestamp, dynamic);
  }

  System& get() { return *system_; }
  [[nodiscard]] const std::string& camera_source() const { return camera_source_; }

 private:
  static ImageView depth_view(const py::handle& depth) {
    if (py::isinstance<py::array>(depth) &&
        py::reinterpret_borrow<py::array>(depth).dtype().is(py::dtype::of<std::uint16_t>()))
      return image_view<std::uint16_t>(depth, "track_rgbd: depth", kOneChannel);
    return image_view<float>(depth, "track_rgbd: depth (uint16 raw or float32 metres)", kOneChannel);
  }

  std::unique_ptr<System> system_;
  std::string camera_source_;
};

py::dict camera_dict(const camera::PinholeCamera& c) {
  return py::dict("name"_a = c.name, "width"_a = c.width, "height"_a = c.height, "fx"_a = c.fx, "fy"_a = c.fy,
                  "cx"_a = c.cx, "cy"_a = c.cy,
                  "distortion"_a = py::make_tuple(c.distortion.k1, c.distortion.k2, c.distortion.p1,
                                                  c.distortion.p2, c.distortion.k3),
                  "rgb_order"_a = c.rgb_order, "depth_map_factor"_a = c.depth_map_factor);
}

py::object snapshot_of(const events::MapSnapshot& s) {
  const auto k = static_cast<py::ssize_t>(s.keyframes.size());
  const auto n = static_cast<py::ssize_t>(s.points.size());
  py::array_t<double> poses({k, py::ssize_t{4}, py::ssize_t{4}}), points({n, py::ssize_t{3}});
  py::array_t<std::uint64_t> keyframe_ids(k), point_ids(n);
  py::array_t<double> stamps(k);
  auto P = poses.mutable_unchecked<3>();
  for (py::ssize_t i = 0; i < k; ++i) {
    const events::KeyframePose& kf = s.keyframes[static_cast<std::size_t>(i)];
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) P(i, r, c) = kf.T_wc.matrix()(r, c);
    keyframe_ids.mutable_at(i) = kf.keyframe_id;
    stamps.mutable_at(i) = kf.timestamp;
  }
  auto X = points.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const events::MapPointSnapshot& p = s.points[static_cast<std::size_t>(i)];
    for (int c = 0; c < 3; ++c) X(i, c) = p.position[c];
    point_ids.mutable_at(i) = p.id;
  }
  return make_namespace(py::dict("points"_a = points, "point_ids"_a = point_ids, "keyframe_poses"_a = poses,
                                 "keyframe_ids"_a = keyframe_ids, "keyframe_timestamps"_a = stamps));
}

py::object dense_of(const dense::PointCloud& cloud) {
  const auto n = static_cast<py::ssize_t>(cloud.size());
  py::array_t<float> points({n, py::ssize_t{3}});
  py::array_t<std::uint8_t> colours({cloud.colours.empty() ? py::ssize_t{0} : n, py::ssize_t{3}});
  auto X = points.mutable_unchecked<2>();
  auto C = colours.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const auto u = static_cast<std::size_t>(i);
    for (int c = 0; c < 3; ++c) X(i, c) = cloud.points[u][c];
    if (!cloud.colours.empty())
      for (int c = 0; c < 3; ++c) C(i, c) = cloud.colours[u][2 - c];  // BGR -> RGB
  }
  return make_namespace(py::dict("points"_a = points, "colours"_a = colours));
}

py::object occupancy_of(const occupancy::Occupancy& o) {
  const occupancy::Grid2d& g = o.grid;
  if (g.width == 0 || g.height == 0) return py::none();
  py::array_t<std::int8_t> cells({static_cast<py::ssize_t>(g.height), static_cast<py::ssize_t>(g.width)});
  std::copy(g.cells.begin(), g.cells.end(), cells.mutable_data());
  py::array_t<double> rotation({3, 3});
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) rotation.mutable_at(r, c) = g.floor.rotation(r, c);
  return make_namespace(py::dict("grid"_a = cells, "resolution"_a = g.resolution,
                                 "origin"_a = py::make_tuple(g.origin.x(), g.origin.y()),
                                 "floor_rotation"_a = rotation, "floor_height"_a = g.floor.height,
                                 "min_height"_a = g.min_height, "max_height"_a = g.max_height));
}

py::dict stats_dict(const MapStats& s) {
  return py::dict("keyframes"_a = s.keyframes, "map_points"_a = s.map_points,
                  "culled_keyframes"_a = s.culled_keyframes, "bundle_adjustments"_a = s.bundle_adjustments,
                  "loops"_a = s.loops, "relocalizations"_a = s.relocalizations,
                  "loaded_keyframes"_a = s.loaded_keyframes, "loaded_map_points"_a = s.loaded_map_points,
                  "global_bundle_adjustments"_a = s.global_bundle_adjustments,
                  "rejected_loops"_a = s.rejected_loops);
}

void bind_track_result(py::module_& m) {
  py::class_<TrackResult>(m, "TrackResult", "What System.track_rgbd did with one frame")
      .def_property_readonly("state",
                             [](const TrackResult& r) { return std::string(tracking::to_string(r.state)); })
      .def_property_readonly("pose",
                             [](const TrackResult& r) {
                               return r.T_wc ? py::object(matrix_of(*r.T_wc)) : py::object(py::none());
                             })
      .def_readonly("inliers", &TrackResult::inliers)
      .def_property_readonly("mask",
                             [](const TrackResult& r) {
                               return r.dynamic.mask.empty() ? py::object(py::none())
                                                             : py::object(mat_view(r.dynamic.mask));
                             })
      .def_property_readonly("timing", [](const TrackResult& r) { return timing_dict(r.timing); })
      .def_property_readonly("keypoints", [](const TrackResult& r) { return r.dynamic.keypoints; })
      .def_property_readonly("geometric_keypoints",
                             [](const TrackResult& r) { return r.dynamic.geometric_keypoints; })
      .def_property_readonly("geometric_seeds",
                             [](const TrackResult& r) { return r.dynamic.geometric_seeds; })
      .def_property_readonly("mask_frame", [](const TrackResult& r) { return r.dynamic.mask_frame; })
      .def_property_readonly("mask_age", [](const TrackResult& r) { return r.dynamic.mask_age; })
      .def_readonly("local_keyframes", &TrackResult::local_keyframes)
      .def_readonly("local_points", &TrackResult::local_points)
      .def("__repr__", [](const TrackResult& r) {
        return "<TrackResult " + std::string(tracking::to_string(r.state)) + ", " +
               std::to_string(r.inliers) + " inliers>";
      });
}

// Calls `f(system)` with the GIL released: these wait for the system's threads or locks, which
// may be delivering events to Python.
template <typename F>
auto released(PySystem& s, F&& f) {
  py::gil_scoped_release release;
  return f(s.get());
}

void bind_queries(py::class_<PySystem>& c) {
  c.def("map_snapshot",
        [](PySystem& s) { return snapshot_of(released(s, [](System& y) { return y.map_snapshot(); })); })
      .def(
          "trajectory",
          [](PySystem& s) { return trajectory_array(released(s, [](System& y) { return y.trajectory(); })); })
      .def("keyframe_trajectory",
           [](PySystem& s) {
             return trajectory_array(released(s, [](System& y) { return y.keyframe_trajectory(); }));
           })
      .def("dense_map",
           [](PySystem& s) { return dense_of(released(s, [](System& y) { return y.dense_map(); })); })
      .def("occupancy",
           [](PySystem& s) { return occupancy_of(released(s, [](System& y) { return y.occupancy(); })); })
      .def("map_stats",
           [](PySystem& s) { return stats_dict(released(s, [](System& y) { return y.map_stats(); })); })
      .def_property_readonly("state",
                             [](PySystem& s) { return std::string(tracking::to_string(s.get().state())); })
      .def_property_readonly("mode",
                             [](PySystem& s) { return std::string(dynamic::to_string(s.get().mode())); })
      .def_property_readonly("segmentation", [](PySystem& s) { return s.get().segmentation_description(); })
      .def_property_readonly("camera", [](PySystem& s) { return camera_dict(s.get().config().camera); })
      .def_property_readonly("camera_source", &PySystem::camera_source)
      .def_property_readonly("dense_enabled", [](PySystem& s) { return s.get().dense_enabled(); })
      .def_property_readonly("publisher_stats", [](PySystem& s) {
        const events::PublisherStats p = s.get().publisher_stats();
        return py::dict("published"_a = p.published, "delivered"_a = p.delivered,
                        "dropped_frames"_a = p.dropped_frames, "max_queued"_a = p.max_queued,
                        "delivery_seconds"_a = p.delivery_seconds);
      });
}

void bind_lifecycle(py::class_<PySystem>& c) {
  c.def(
       "save_trajectory",
       [](PySystem& s, const fs::path& f) { released(s, [&](System& y) { y.save_trajectory_tum(f); }); },
       "file"_a)
      .def(
          "save_keyframe_trajectory",
          [](PySystem& s, const fs::path& f) {
            released(s, [&](System& y) { y.save_keyframe_trajectory_tum(f); });
          },
          "file"_a)
      .def(
          "save_map", [](PySystem& s, const fs::path& f) { released(s, [&](System& y) { y.save_map(f); }); },
          "file"_a)
      .def(
          "load_map", [](PySystem& s, const fs::path& f) { released(s, [&](System& y) { y.load_map(f); }); },
          "file"_a)
      .def(
          "subscribe",
          [](PySystem& s, py::function cb) { s.get().subscribe(make_subscriber(std::move(cb))); },
          "callback"_a)
      .def("shutdown", [](PySystem& s) { released(s, [](System& y) { y.shutdown(); }); })
      .def("reset", [](PySystem& s) { released(s, [](System& y) { y.reset(); }); })
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](PySystem& s, const py::args&) { released(s, [](System& y) { y.shutdown(); }); });
}

}  // namespace

void bind_system(py::module_& m) {
  bind_track_result(m);
  py::class_<PySystem> c(m, "System", "RGB-D SLAM in scenes with people: lrd::System (docs/python.md)");
  c.def(py::init([](py::object config, py::object sequence, std::optional<fs::path> settings,
                    std::optional<std::string> preset, std::optional<std::string> mode,
                    std::optional<std::string> segmenter, std::optional<fs::path> segmenter_model, bool dense,
                    std::optional<bool> occupancy, bool deterministic, bool loop_closing,
                    std::optional<fs::path> vocabulary, bool localization_only, bool yardstick) {
          SystemArgs a{std::move(config),
                       std::move(sequence),
                       std::move(settings),
                       std::move(preset),
                       std::move(mode),
                       std::move(segmenter),
                       std::move(segmenter_model),
                       dense,
                       occupancy,
                       deterministic,
                       loop_closing,
                       std::move(vocabulary),
                       localization_only,
                       yardstick};
          return std::make_unique<PySystem>(a);
        }),
        "config"_a = py::none(), py::kw_only(), "sequence"_a = py::none(), "settings"_a = py::none(),
        "preset"_a = py::none(), "mode"_a = py::none(), "segmenter"_a = py::none(),
        "segmenter_model"_a = py::none(), "dense"_a = false, "occupancy"_a = py::none(),
        "deterministic"_a = false, "loop_closing"_a = true, "vocabulary"_a = py::none(),
        "localization_only"_a = false, "yardstick"_a = false);
  c.def("track_rgbd", &PySystem::track, "rgb"_a, "depth"_a, "timestamp"_a, py::kw_only(), "order"_a = "rgb",
        "mask"_a = py::none());
  bind_queries(c);
  bind_lifecycle(c);
}

}  // namespace lrd::python
