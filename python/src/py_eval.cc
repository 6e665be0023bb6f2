// lrdslam.eval: the numbers `lrdslam eval` prints (TUM's evaluate_ate.py / evaluate_rpe.py).
#include <fmt/format.h>

#include "lrd/eval/ate.h"
#include "lrd/eval/improvement.h"
#include "lrd/eval/rpe.h"
#include "lrd/util/error.h"
#include "numpy_mat.h"
#include "py_common.h"

namespace lrd::python {

namespace {

using py::literals::operator""_a;

py::dict stats_fields(const eval::ErrorStats& s) {
  return py::dict("rmse"_a = s.rmse, "mean"_a = s.mean, "median"_a = s.median, "std"_a = s.std_dev,
                  "min"_a = s.min, "max"_a = s.max, "pairs"_a = s.count);
}

// Evaluates with the evaluator's message prefixed by what was compared, as `lrdslam eval` says it.
template <typename F>
auto compared(const py::handle& gt, const py::handle& est, F&& evaluate) {
  const io::Trajectory ground_truth = trajectory_of(gt, "ground truth");
  const io::Trajectory estimate = trajectory_of(est, "estimate");
  const auto name = [](const py::handle& h, const char* fallback) {
    return py::isinstance<py::array>(h) ? std::string(fallback) : py::str(h).cast<std::string>();
  };
  try {
    return evaluate(ground_truth, estimate);
  } catch (const Error& e) {
    throw Error(fmt::format("{} vs ground truth {}: {}", name(est, "estimate"), name(gt, "array"), e.what()));
  }
}

}  // namespace

void bind_eval(py::module_& m) {
  m.def(
      "ate",
      [](const py::handle& gt, const py::handle& est, double max_dt) {
        const eval::AteResult r = compared(gt, est, [&](const io::Trajectory& g, const io::Trajectory& e) {
          return eval::compute_ate(g, e, max_dt);
        });
        py::dict fields = stats_fields(r.stats);
        fields["alignment"] = matrix_of(r.alignment);
        fields["errors"] = py::array_t<double>(static_cast<py::ssize_t>(r.errors.size()), r.errors.data());
        return make_namespace(fields);
      },
      "ground_truth"_a, "estimate"_a, py::kw_only(), "max_dt"_a = 0.02,
      "Absolute trajectory error in metres, as `lrdslam eval` computes it (files or N x 8 arrays)");
  m.def(
      "rpe",
      [](const py::handle& gt, const py::handle& est, double delta) {
        const eval::RpeResult r = compared(gt, est, [&](const io::Trajectory& g, const io::Trajectory& e) {
          return eval::compute_rpe(g, e, delta);
        });
        return make_namespace(py::dict("trans"_a = make_namespace(stats_fields(r.trans)),
                                       "rot"_a = make_namespace(stats_fields(r.rot)), "delta"_a = delta));
      },
      "ground_truth"_a, "estimate"_a, py::kw_only(), "delta"_a = 1.0,
      "Relative pose error over pairs `delta` seconds apart: trans in metres, rot in degrees");
  m.def(
      "improvement", [](double baseline, double ours) { return eval::improvement_percent(baseline, ours); },
      "baseline"_a, "ours"_a, "The paper's improvement rate eta = (baseline - ours) / baseline * 100 %");
}

}  // namespace lrd::python
