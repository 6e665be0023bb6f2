// The extension behind the `lrdslam` package (python/lrdslam/__init__.py re-exports it): the
// library's System, its events, sequences, the renderer and the evaluators, for /usr/bin/python3.
#include <pybind11/pybind11.h>

#include "lrd/util/error.h"
#include "numpy_mat.h"
#include "py_common.h"

namespace py = pybind11;
using py::literals::operator""_a;

PYBIND11_MODULE(_core, m) {
  m.doc() = "lrd-slam: RGB-D SLAM for scenes with people (docs/python.md)";
  m.attr("__version__") = LRD_VERSION;
  // The library's one-line errors (a file and its problem, a bad argument) as lrdslam.Error.
  py::register_exception<lrd::Error>(m, "Error", PyExc_RuntimeError);
  py::module_ events = m.def_submodule("events", "What System.subscribe delivers");
  py::module_ io = m.def_submodule("io", "Sequences: TUM-layout folders and bags");
  py::module_ synth = m.def_submodule("synth", "The synthetic benchmark's frames");
  py::module_ eval = m.def_submodule("eval", "ATE and RPE as `lrdslam eval` computes them");
  lrd::python::bind_events(events);
  lrd::python::bind_system(m);
  lrd::python::bind_sources(io, synth);
  lrd::python::bind_eval(eval);
  m.def(
      "_image_address",
      [](const py::handle& array) {
        // What track_rgbd would hand the system for this colour array: the address of the pixels
        // it wraps (the array's own when no copy is made). For tests and the curious.
        const auto view = lrd::python::image_view<std::uint8_t>(
            array, "image", lrd::python::kOneChannel | lrd::python::kThreeChannels);
        return reinterpret_cast<std::uintptr_t>(view.mat.data);
      },
      "array"_a);
}
