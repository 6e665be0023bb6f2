#include "py_events.h"

#include <pybind11/stl.h>
#include <spdlog/spdlog.h>

#include <string>
#include <utility>

#include "numpy_mat.h"
#include "py_common.h"

namespace lrd::python {

namespace {

// N x 2 float32 array of image points (a copy).
py::array_t<float> points_array(const std::vector<cv::Point2f>& points) {
  py::array_t<float> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{2}});
  auto a = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i) {
    a(static_cast<py::ssize_t>(i), 0) = points[i].x;
    a(static_cast<py::ssize_t>(i), 1) = points[i].y;
  }
  return out;
}

py::object optional_view(const cv::Mat& m) {
  return m.empty() ? py::object(py::none()) : py::object(mat_view(m));
}

class PythonSubscriber final : public events::Subscriber {
 public:
  explicit PythonSubscriber(py::function callback) : callback_(std::move(callback)) {}
  ~PythonSubscriber() override {
    // Destroyed where the system is, with the GIL released around its threads' shutdown.
    py::gil_scoped_acquire gil;
    if (errors_ > 1) spdlog::warn("Python event callback: {} more exceptions after the first", errors_ - 1);
    callback_ = py::function();
  }
  PythonSubscriber(const PythonSubscriber&) = delete;
  PythonSubscriber& operator=(const PythonSubscriber&) = delete;

  void on_frame(const events::FrameTracked& e) override { deliver(e); }
  void on_keyframe(const events::KeyframeInserted& e) override { deliver(e); }
  void on_loop(const events::LoopClosed& e) override { deliver(e); }
  void on_map_changed(const events::MapChanged& e) override { deliver(e); }
  void on_dense_map(const events::DenseMapUpdated& e) override { deliver(e); }

 private:
  template <typename Event>
  void deliver(const Event& event) {
    py::gil_scoped_acquire gil;
    try {
      callback_(py::cast(event));
    } catch (py::error_already_set& error) {
      // The first with its traceback through sys.unraisablehook; the rest counted.
      if (errors_++ == 0) {
        error.discard_as_unraisable("lrdslam event callback");
      } else {
        error.restore();
        PyErr_Clear();
      }
    }
  }

  py::function callback_;
  std::size_t errors_ = 0;
};

void bind_frame_event(py::module_& m) {
  using events::FrameTracked;
  py::class_<FrameTracked>(m, "FrameTracked", "A frame was tracked (or not): System.subscribe")
      .def_property_readonly("kind", [](const FrameTracked&) { return "frame"; })
      .def_readonly("map", &FrameTracked::map)
      .def_readonly("frame_id", &FrameTracked::frame_id)
      .def_readonly("timestamp", &FrameTracked::timestamp)
      .def_property_readonly("state",
                             [](const FrameTracked& e) { return std::string(tracking::to_string(e.state)); })
      .def_property_readonly("pose",
                             [](const FrameTracked& e) {
                               return e.T_wc ? py::object(matrix_of(*e.T_wc)) : py::object(py::none());
                             })
      .def_property_readonly("timing", [](const FrameTracked& e) { return timing_dict(e.timing); })
      .def_readonly("inliers", &FrameTracked::inliers)
      .def_readonly("mask_frame", &FrameTracked::mask_frame)
      .def_readonly("mask_age", &FrameTracked::mask_age)
      .def_readonly("geometric_keypoints", &FrameTracked::geometric_keypoints)
      .def_readonly("relocalized", &FrameTracked::relocalized)
      .def_readonly("new_keyframe", &FrameTracked::new_keyframe)
      .def_property_readonly("grey", [](const FrameTracked& e) { return optional_view(e.grey); })
      .def_property_readonly("mask", [](const FrameTracked& e) { return optional_view(e.mask); })
      .def_property_readonly("kept_keypoints",
                             [](const FrameTracked& e) { return points_array(e.kept_keypoints); })
      .def_property_readonly("removed_keypoints",
                             [](const FrameTracked& e) { return points_array(e.removed_keypoints); });
}

void bind_map_events(py::module_& m) {
  using events::KeyframeInserted;
  using events::LoopClosed;
  using events::MapChanged;
  py::class_<KeyframeInserted>(m, "KeyframeInserted", "A frame became a keyframe")
      .def_property_readonly("kind", [](const KeyframeInserted&) { return "keyframe"; })
      .def_readonly("map", &KeyframeInserted::map)
      .def_readonly("keyframe_id", &KeyframeInserted::keyframe_id)
      .def_readonly("frame_id", &KeyframeInserted::frame_id)
      .def_readonly("timestamp", &KeyframeInserted::timestamp)
      .def_property_readonly("pose", [](const KeyframeInserted& e) { return matrix_of(e.T_wc); })
      .def_readonly("map_points", &KeyframeInserted::map_points);
  py::class_<LoopClosed>(m, "LoopClosed", "A loop was closed; `corrected` holds every keyframe's new pose")
      .def_property_readonly("kind", [](const LoopClosed&) { return "loop"; })
      .def_readonly("map", &LoopClosed::map)
      .def_readonly("frame_id", &LoopClosed::frame_id)
      .def_readonly("timestamp", &LoopClosed::timestamp)
      .def_readonly("keyframe_id", &LoopClosed::keyframe_id)
      .def_readonly("loop_keyframe_id", &LoopClosed::loop_keyframe_id)
      .def_readonly("inliers", &LoopClosed::inliers)
      .def_readonly("correction_m", &LoopClosed::correction_m)
      .def_property_readonly("corrected", [](const LoopClosed& e) {
        py::dict poses;  // keyframe id -> 4x4 camera-to-world
        for (const events::KeyframePose& k : e.corrected) poses[py::int_(k.keyframe_id)] = matrix_of(k.T_wc);
        return poses;
      });
  py::class_<MapChanged>(m, "MapChanged", "Local mapping finished a keyframe")
      .def_property_readonly("kind", [](const MapChanged&) { return "map"; })
      .def_readonly("map", &MapChanged::map)
      .def_readonly("keyframe_id", &MapChanged::keyframe_id)
      .def_readonly("keyframes", &MapChanged::keyframes)
      .def_readonly("map_points", &MapChanged::map_points)
      .def_readonly("culled_keyframes", &MapChanged::culled_keyframes)
      .def_readonly("triangulated_points", &MapChanged::triangulated_points);
  using events::DenseMapUpdated;
  py::class_<DenseMapUpdated>(m, "DenseMapUpdated", "The dense stage integrated a keyframe")
      .def_property_readonly("kind", [](const DenseMapUpdated&) { return "dense"; })
      .def_readonly("map", &DenseMapUpdated::map)
      .def_readonly("timestamp", &DenseMapUpdated::timestamp)
      .def_readonly("keyframes", &DenseMapUpdated::keyframes)
      .def_readonly("dynamic_pixels", &DenseMapUpdated::dynamic_pixels)
      .def_readonly("filled_pixels", &DenseMapUpdated::filled_pixels);
}

}  // namespace

std::shared_ptr<events::Subscriber> make_subscriber(py::function callback) {
  return std::make_shared<PythonSubscriber>(std::move(callback));
}

void bind_events(py::module_& m) {
  bind_frame_event(m);
  bind_map_events(m);
}

}  // namespace lrd::python
