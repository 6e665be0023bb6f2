#include "numpy_mat.h"

#include <fmt/format.h>

#include <cstdint>

#include "lrd/util/error.h"

namespace lrd::python {

namespace {

std::string dtype_name(const py::dtype& d) {
  return d.attr("name").cast<std::string>();
}

// True when the array's memory is a row-strided image: pixels and channels packed within a row,
// rows at a positive stride OpenCV can express (cv::Mat's step).
bool wraps_as_mat(const py::array& a, int channels, std::size_t item) {
  const auto n = static_cast<py::ssize_t>(item);
  if (a.ndim() == 3 && a.strides(2) != n) return false;
  if (a.strides(1) != channels * n) return false;
  return a.strides(0) >= a.shape(1) * channels * n && a.strides(0) % n == 0;
}

}  // namespace

template <typename Dtype>
ImageView image_view(const py::handle& object, const char* what, int channels_allowed_mask) {
  if (!py::isinstance<py::array>(object))
    throw Error(fmt::format("{}: expected a numpy array, got {}", what,
                            py::str(object.get_type().attr("__name__")).cast<std::string>()));
  auto array = py::reinterpret_borrow<py::array>(object);
  const py::dtype wanted = py::dtype::of<Dtype>();
  if (!array.dtype().is(wanted))
    throw Error(
        fmt::format("{}: expected dtype {}, got {}", what, dtype_name(wanted), dtype_name(array.dtype())));
  const int channels = array.ndim() == 3 ? static_cast<int>(array.shape(2)) : 1;
  const bool shape_ok = (array.ndim() == 2 || array.ndim() == 3) && channels < 31 &&
                        ((channels_allowed_mask >> channels) & 1) != 0;
  if (!shape_ok) {
    std::string shape;
    // fmt, not string concatenation: gcc 12 warns of a false overlap in operator+ here.
    for (py::ssize_t d = 0; d < array.ndim(); ++d) shape += fmt::format("{}{}", d ? "x" : "", array.shape(d));
    throw Error(fmt::format("{}: expected an {} array, got shape ({})", what,
                            channels_allowed_mask == kOneChannel ? "HxW" : "HxWx3 (or HxW grey)", shape));
  }
  if (array.shape(0) == 0 || array.shape(1) == 0) throw Error(fmt::format("{}: the image is empty", what));
  if (!wraps_as_mat(array, channels, sizeof(Dtype)))
    array = py::array::ensure(array, py::array::c_style);  // a copy OpenCV can address
  ImageView view;
  view.mat = cv::Mat(static_cast<int>(array.shape(0)), static_cast<int>(array.shape(1)),
                     CV_MAKETYPE(cv::DataType<Dtype>::depth, channels), const_cast<void*>(array.data()),
                     static_cast<std::size_t>(array.strides(0)));
  view.owner = std::move(array);
  return view;
}

template ImageView image_view<std::uint8_t>(const py::handle&, const char*, int);
template ImageView image_view<std::uint16_t>(const py::handle&, const char*, int);
template ImageView image_view<float>(const py::handle&, const char*, int);

py::array mat_view(const cv::Mat& mat) {
  py::dtype dtype;
  switch (mat.depth()) {
    case CV_8U:
      dtype = py::dtype::of<std::uint8_t>();
      break;
    case CV_8S:
      dtype = py::dtype::of<std::int8_t>();
      break;
    case CV_16U:
      dtype = py::dtype::of<std::uint16_t>();
      break;
    case CV_16S:
      dtype = py::dtype::of<std::int16_t>();
      break;
    case CV_32S:
      dtype = py::dtype::of<std::int32_t>();
      break;
    case CV_32F:
      dtype = py::dtype::of<float>();
      break;
    default:
      dtype = py::dtype::of<double>();
      break;
  }
  auto* kept = new cv::Mat(mat);  // shares the buffer: the capsule holds one reference
  py::capsule owner(kept, [](void* p) { delete static_cast<cv::Mat*>(p); });
  const auto item = static_cast<py::ssize_t>(mat.elemSize1());
  std::vector<py::ssize_t> shape{mat.rows, mat.cols};
  std::vector<py::ssize_t> strides{static_cast<py::ssize_t>(mat.step[0]),
                                   static_cast<py::ssize_t>(mat.elemSize())};
  if (mat.channels() > 1) {
    shape.push_back(mat.channels());
    strides.push_back(item);
  }
  return py::array(dtype, shape, strides, kept->data, owner);
}

py::array_t<double> matrix_of(const Eigen::Isometry3d& pose) {
  py::array_t<double> out({4, 4});
  auto m = out.mutable_unchecked<2>();
  const Eigen::Matrix4d& p = pose.matrix();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = p(r, c);
  return out;
}

Eigen::Isometry3d isometry_of(const py::handle& object, const char* what) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(object);
  if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
    throw Error(fmt::format("{}: expected a 4x4 array", what));
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = a.at(r, c);
  const Eigen::Matrix3d rotation = m.topLeftCorner<3, 3>();
  if (!((rotation * rotation.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-6))
    throw Error(fmt::format("{}: the upper-left 3x3 is not a rotation", what));
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation;
  pose.translation() = m.topRightCorner<3, 1>();
  return pose;
}

}  // namespace lrd::python
