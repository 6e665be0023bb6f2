#pragma once
// What the Python module's files share: how the library's values become Python values.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <filesystem>
#include <memory>

#include "app/bag_input.h"
#include "lrd/events/events.h"
#include "lrd/io/frame_source.h"
#include "lrd/io/trajectory.h"

namespace lrd::python {

namespace py = pybind11;

// A types.SimpleNamespace of `fields`: results read as attributes (snapshot.points).
[[nodiscard]] py::object make_namespace(const py::dict& fields);

// An N x 8 float64 array in TUM's column order: t tx ty tz qx qy qz qw (qw >= 0, as written).
[[nodiscard]] py::array_t<double> trajectory_array(const io::Trajectory& trajectory);
// A trajectory from a TUM file's path or an N x 8 array; throws lrd::Error naming `what`.
[[nodiscard]] io::Trajectory trajectory_of(const py::handle& object, const char* what);

// Seconds per stage, and `total` as the run's per-frame time counts it.
[[nodiscard]] py::dict timing_dict(const events::FrameTiming& timing);

// A recorded sequence as `lrdslam run` opens it: a TUM-layout folder, else a bag (the CLI's
// opener, with its topic options).
[[nodiscard]] std::shared_ptr<const io::FrameSource> open_source(const std::filesystem::path& path,
                                                                 const app::BagCli& bag);

// A sequence for Python: frames decoded on demand, with the depth unit `lrdslam run` would use.
struct Sequence {
  std::shared_ptr<const io::FrameSource> source;
  double depth_factor = 5000.0;
};

void bind_events(py::module_& m);
void bind_system(py::module_& m);
void bind_sources(py::module_& io, py::module_& synth);
void bind_eval(py::module_& eval);

}  // namespace lrd::python
