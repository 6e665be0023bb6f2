#pragma once
// numpy arrays <-> cv::Mat for the Python module. Inputs are wrapped, not copied, whenever their
// memory is a row-strided image (every C-contiguous array and row slices of one); outputs are
// numpy views that keep the cv::Mat's buffer alive through a capsule.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <string>

namespace lrd::python {

namespace py = pybind11;

// A Mat header over a numpy array's memory, and the array that owns that memory (the caller's
// own, or a contiguous copy when the layout could not be wrapped). Keep `owner` while `mat` is used.
struct ImageView {
  py::array owner;
  cv::Mat mat;
};

// `array` as a CV_<depth>C<channels> image: an HxW (channels 1) or HxWxC array of dtype `Dtype`.
// Throws lrd::Error naming `what` for another dtype or shape.
template <typename Dtype>
[[nodiscard]] ImageView image_view(const py::handle& array, const char* what, int channels_allowed_mask);

// The channel counts image_view accepts, as a bit mask (bit c set: c channels).
constexpr int kOneChannel = 1 << 1;
constexpr int kThreeChannels = 1 << 3;

// A numpy view of `mat` (HxW or HxWxC) that shares its buffer and holds a reference to it.
[[nodiscard]] py::array mat_view(const cv::Mat& mat);

// 4x4 float64 array of a rigid transform (a copy).
[[nodiscard]] py::array_t<double> matrix_of(const Eigen::Isometry3d& pose);
// The rigid transform of a 4x4 array; throws lrd::Error naming `what` for another shape.
[[nodiscard]] Eigen::Isometry3d isometry_of(const py::handle& array, const char* what);

}  // namespace lrd::python
