#include "lrd/eval/plot.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "lrd/eval/statistics.h"
#include "lrd/io/image_file.h"
#include "lrd/util/error.h"

namespace lrd::eval {
namespace {

const cv::Scalar kBlack(0, 0, 0);
const cv::Scalar kGrey(200, 200, 200);
const cv::Scalar kBlue(200, 90, 20);  // BGR
const cv::Scalar kRed(40, 40, 220);
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kFontScale = 0.45;

struct Range {
  double lo = 0.0, hi = 1.0;
  void include(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  [[nodiscard]] double span() const { return hi - lo; }
};

Range empty_range() {
  return {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
}

// Grows a degenerate range and adds a margin so lines do not touch the frame.
Range padded(Range r, double fraction) {
  if (!(r.span() > 0.0)) {
    const double half = std::max(std::abs(r.lo) * 0.05, 0.5);
    r = {r.lo - half, r.hi + half};
  }
  const double pad = r.span() * fraction;
  return {r.lo - pad, r.hi + pad};
}

// A "nice" tick step (1, 2 or 5 times a power of ten) giving roughly `target` ticks.
double tick_step(double span, int target) {
  const double raw = span / target;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (raw <= m * magnitude) return m * magnitude;
  }
  return 10.0 * magnitude;
}

std::string tick_label(double value, double step) {
  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  if (std::abs(value) < step * 1e-6) value = 0.0;  // no "-0.00"
  return fmt::format("{:.{}f}", value, decimals);
}

// Data-to-pixel mapping of one plot area, with its frame, ticks and labels.
class Axes {
 public:
  Axes(cv::Mat& canvas, cv::Rect area, Range x, Range y) : canvas_(canvas), area_(area), x_(x), y_(y) {}

  [[nodiscard]] cv::Point2d to_pixel(double x, double y) const {
    return {area_.x + (x - x_.lo) / x_.span() * area_.width,
            area_.y + area_.height - (y - y_.lo) / y_.span() * area_.height};
  }

  void line(double x0, double y0, double x1, double y1, const cv::Scalar& colour, int thickness = 1) const {
    cv::line(canvas_, to_fixed(to_pixel(x0, y0)), to_fixed(to_pixel(x1, y1)), colour, thickness, cv::LINE_AA,
             kShift);
  }

  void draw_frame(const std::string& x_label, const std::string& y_label, const std::string& title) const {
    const double sx = tick_step(x_.span(), 6), sy = tick_step(y_.span(), 6);
    for (double v = std::ceil(x_.lo / sx) * sx; v <= x_.hi + 1e-12; v += sx) {
      const int px = static_cast<int>(std::lround(to_pixel(v, y_.lo).x));
      cv::line(canvas_, {px, area_.y}, {px, area_.y + area_.height}, kGrey, 1);
      cv::line(canvas_, {px, area_.y + area_.height}, {px, area_.y + area_.height + 5}, kBlack, 1);
      put_centred(tick_label(v, sx), {px, area_.y + area_.height + 20});
    }
    for (double v = std::ceil(y_.lo / sy) * sy; v <= y_.hi + 1e-12; v += sy) {
      const int py = static_cast<int>(std::lround(to_pixel(x_.lo, v).y));
      cv::line(canvas_, {area_.x, py}, {area_.x + area_.width, py}, kGrey, 1);
      cv::line(canvas_, {area_.x - 5, py}, {area_.x, py}, kBlack, 1);
      const std::string label = tick_label(v, sy);
      const cv::Size size = text_size(label);
      cv::putText(canvas_, label, {area_.x - 8 - size.width, py + size.height / 2}, kFont, kFontScale, kBlack,
                  1, cv::LINE_AA);
    }
    cv::rectangle(canvas_, area_, kBlack, 1);
    put_centred(x_label, {area_.x + area_.width / 2, area_.y + area_.height + 45});
    put_centred(title, {area_.x + area_.width / 2, area_.y - 15});
    // OpenCV cannot rotate text; the y label sits above the axis instead.
    cv::putText(canvas_, y_label, {std::max(2, area_.x - 60), area_.y - 15}, kFont, kFontScale, kBlack, 1,
                cv::LINE_AA);
  }

  // Legend entries (colour, text) in the top-right corner of the plot area.
  void draw_legend(const std::vector<std::pair<cv::Scalar, std::string>>& entries) const {
    int width = 0;
    for (const auto& [colour, text] : entries) width = std::max(width, text_size(text).width);
    const int row = 20;
    const cv::Rect box(area_.x + area_.width - width - 55, area_.y + 8, width + 45,
                       row * static_cast<int>(entries.size()) + 8);
    cv::rectangle(canvas_, box, cv::Scalar(255, 255, 255), cv::FILLED);
    cv::rectangle(canvas_, box, kBlack, 1);
    int y = box.y + 4 + row / 2;
    for (const auto& [colour, text] : entries) {
      cv::line(canvas_, {box.x + 6, y}, {box.x + 30, y}, colour, 2, cv::LINE_AA);
      cv::putText(canvas_, text, {box.x + 36, y + 5}, kFont, kFontScale, kBlack, 1, cv::LINE_AA);
      y += row;
    }
  }

 private:
  static constexpr int kShift = 4;  // sub-pixel line endpoints

  static cv::Point to_fixed(cv::Point2d p) {
    return {static_cast<int>(std::lround(p.x * (1 << kShift))),
            static_cast<int>(std::lround(p.y * (1 << kShift)))};
  }
  static cv::Size text_size(const std::string& text) {
    int baseline = 0;
    return cv::getTextSize(text, kFont, kFontScale, 1, &baseline);
  }
  void put_centred(const std::string& text, cv::Point centre) const {
    const cv::Size size = text_size(text);
    cv::putText(canvas_, text, {centre.x - size.width / 2, centre.y}, kFont, kFontScale, kBlack, 1,
                cv::LINE_AA);
  }

  cv::Mat& canvas_;
  cv::Rect area_;
  Range x_, y_;
};

void save(const std::filesystem::path& file, const cv::Mat& image) {
  io::write_image_file(file, image);
}

// Polyline broken where the stamps jump by 2x the median period, like plot_traj() in evaluate_ate.py.
void draw_trajectory(const Axes& axes, const std::vector<double>& stamps,
                     const std::vector<Eigen::Vector3d>& xyz, int ax, int ay, const cv::Scalar& colour) {
  std::vector<double> periods;
  for (std::size_t k = 1; k < stamps.size(); ++k) periods.push_back(stamps[k] - stamps[k - 1]);
  const double max_gap = periods.empty() ? 0.0 : 2.0 * median(periods);
  for (std::size_t k = 1; k < xyz.size(); ++k) {
    if (stamps[k] - stamps[k - 1] >= max_gap) continue;
    axes.line(xyz[k - 1][ax], xyz[k - 1][ay], xyz[k][ax], xyz[k][ay], colour, 2);
  }
}

void plot_top_view(const std::filesystem::path& file, const io::Trajectory& gt, const io::Trajectory& est,
                   const AteResult& ate) {
  std::vector<Eigen::Vector3d> gt_xyz, est_xyz;
  for (const auto& p : gt) gt_xyz.push_back(p.pose.translation());
  for (const auto& p : est) est_xyz.push_back(ate.alignment * p.pose.translation());

  // The two axes along which the ground truth extends most, in x, y, z order.
  std::array<Range, 3> gt_range{empty_range(), empty_range(), empty_range()};
  for (const auto& p : gt_xyz) {
    for (int a = 0; a < 3; ++a) gt_range[a].include(p[a]);
  }
  std::array<int, 3> order{0, 1, 2};
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return gt_range[a].span() > gt_range[b].span(); });
  const int ax = std::min(order[0], order[1]), ay = std::max(order[0], order[1]);

  Range rx = empty_range(), ry = empty_range();
  for (const auto* set : {&gt_xyz, &est_xyz}) {
    for (const auto& p : *set) {
      rx.include(p[ax]);
      ry.include(p[ay]);
    }
  }
  rx = padded(rx, 0.05);
  ry = padded(ry, 0.05);
  // Equal scale on both axes: widen the range that is relatively shorter.
  const cv::Rect area(90, 50, 760, 640);
  const double scale = std::max(rx.span() / area.width, ry.span() / area.height);
  const double cx = (rx.lo + rx.hi) / 2, cy = (ry.lo + ry.hi) / 2;
  rx = {cx - scale * area.width / 2, cx + scale * area.width / 2};
  ry = {cy - scale * area.height / 2, cy + scale * area.height / 2};

  cv::Mat canvas(area.y + area.height + 70, area.x + area.width + 30, CV_8UC3, cv::Scalar(255, 255, 255));
  const Axes axes(canvas, area, rx, ry);
  const char* names[] = {"x", "y", "z"};
  axes.draw_frame(fmt::format("{} [m]", names[ax]), fmt::format("{} [m]", names[ay]),
                  fmt::format("ATE: RMSE {:.4f} m over {} pairs", ate.stats.rmse, ate.stats.count));
  for (const Match& m : ate.matches) {
    const Eigen::Vector3d& g = gt_xyz[m.first];
    const Eigen::Vector3d& e = est_xyz[m.second];
    axes.line(g[ax], g[ay], e[ax], e[ay], kRed, 1);
  }
  draw_trajectory(axes, timestamps(gt), gt_xyz, ax, ay, kBlack);
  draw_trajectory(axes, timestamps(est), est_xyz, ax, ay, kBlue);
  axes.draw_legend({{kBlack, "ground truth"}, {kBlue, "estimated (aligned)"}, {kRed, "difference"}});
  save(file, canvas);
}

void plot_ape_over_time(const std::filesystem::path& file, const io::Trajectory& gt, const AteResult& ate) {
  const double t0 = gt[ate.matches.front().first].timestamp;
  std::vector<double> t;
  for (const Match& m : ate.matches) t.push_back(gt[m.first].timestamp - t0);
  Range rx{0.0, std::max(t.back(), 1e-3)};
  Range ry{0.0, *std::max_element(ate.errors.begin(), ate.errors.end())};
  ry = padded(ry, 0.08);
  ry.lo = 0.0;

  const cv::Rect area(90, 50, 760, 400);
  cv::Mat canvas(area.y + area.height + 70, area.x + area.width + 30, CV_8UC3, cv::Scalar(255, 255, 255));
  const Axes axes(canvas, area, rx, ry);
  axes.draw_frame(
      "time [s]", "APE [m]",
      fmt::format("absolute position error (RMSE {:.4f} m, max {:.4f} m)", ate.stats.rmse, ate.stats.max));
  axes.line(rx.lo, ate.stats.rmse, rx.hi, ate.stats.rmse, kRed, 1);
  for (std::size_t k = 1; k < t.size(); ++k)
    axes.line(t[k - 1], ate.errors[k - 1], t[k], ate.errors[k], kBlue, 2);
  axes.draw_legend({{kBlue, "APE"}, {kRed, "RMSE"}});
  save(file, canvas);
}

}  // namespace

void write_ate_plots(const std::filesystem::path& dir, const io::Trajectory& ground_truth,
                     const io::Trajectory& estimate, const AteResult& ate) {
  if (ate.matches.empty()) throw Error("no associated pairs to plot");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw file_error(dir, "cannot create plot directory: " + ec.message());
  plot_top_view(dir / "trajectory_top.png", ground_truth, estimate, ate);
  plot_ape_over_time(dir / "ape_over_time.png", ground_truth, ate);
}

}  // namespace lrd::eval
