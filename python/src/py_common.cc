#include "py_common.h"

#include <fmt/format.h>
#include <pybind11/stl/filesystem.h>

#include "lrd/io/tum_sequence.h"
#include "lrd/util/error.h"

namespace lrd::python {

namespace fs = std::filesystem;
using py::literals::operator""_a;

py::object make_namespace(const py::dict& fields) {
  return py::module_::import("types").attr("SimpleNamespace")(**fields);
}

py::array_t<double> trajectory_array(const io::Trajectory& trajectory) {
  py::array_t<double> out({static_cast<py::ssize_t>(trajectory.size()), py::ssize_t{8}});
  auto a = out.mutable_unchecked<2>();
  for (std::size_t k = 0; k < trajectory.size(); ++k) {
    const auto i = static_cast<py::ssize_t>(k);
    const io::StampedPose& p = trajectory[k];
    // As io::write_trajectory_tum writes it.
    Eigen::Quaterniond q(p.pose.linear());
    q.normalize();
    if (q.w() < 0.0) q.coeffs() = -q.coeffs();
    const Eigen::Vector3d t = p.pose.translation();
    const double row[8] = {p.timestamp, t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
    for (int c = 0; c < 8; ++c) a(i, c) = row[c];
  }
  return out;
}

io::Trajectory trajectory_of(const py::handle& object, const char* what) {
  if (py::isinstance<py::str>(object) || py::hasattr(object, "__fspath__"))
    return io::read_trajectory_tum(object.cast<fs::path>());
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(object);
  if (!a || a.ndim() != 2 || a.shape(1) != 8)
    throw Error(
        fmt::format("{}: expected a TUM trajectory file or an N x 8 array (t tx ty tz qx qy qz qw)", what));
  io::Trajectory out;
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    const Eigen::Quaterniond q(a.at(i, 7), a.at(i, 4), a.at(i, 5), a.at(i, 6));
    if (!(q.norm() > 0.0)) throw Error(fmt::format("{}: row {} has no rotation (zero quaternion)", what, i));
    io::StampedPose p;
    p.timestamp = a.at(i, 0);
    p.pose.linear() = q.normalized().toRotationMatrix();
    p.pose.translation() = Eigen::Vector3d(a.at(i, 1), a.at(i, 2), a.at(i, 3));
    if (!out.empty() && !(p.timestamp > out.back().timestamp))
      throw Error(fmt::format("{}: row {}'s timestamp {:.6f} does not increase", what, i, p.timestamp));
    out.push_back(p);
  }
  return out;
}

py::dict timing_dict(const events::FrameTiming& t) {
  return py::dict("extraction"_a = t.extraction, "segmentation"_a = t.segmentation,
                  "mask_wait"_a = t.mask_wait, "geometry"_a = t.geometry, "tracking"_a = t.tracking,
                  "waiting"_a = t.waiting, "mapping"_a = t.mapping, "yardstick"_a = t.yardstick,
                  "total"_a = t.total());
}

std::shared_ptr<const io::FrameSource> open_source(const fs::path& path, const app::BagCli& bag) {
  std::error_code ec;
  // A rosbag2 folder holds metadata.yaml; any other folder is a TUM-layout sequence.
  if (fs::is_directory(path, ec) && !fs::exists(path / "metadata.yaml", ec))
    return std::make_shared<const io::TumSequence>(io::TumSequence::open(path));
  if (!fs::exists(path, ec)) throw file_error(path, "no such sequence folder or bag");
  app::BagCli cli = bag;
  cli.bag = path.string();
  return app::open_bag(cli);
}

}  // namespace lrd::python
