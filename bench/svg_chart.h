#pragma once
// A small SVG line chart for the benchmarks' results in bench/results (Debian's Python here has no
// matplotlib, and a results page should not need a browser script to show a curve): panels stacked
// one under another, sharing the x axis, each with its own y range and a legend.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace lrd::bench {

struct ChartSeries {
  std::string label;
  std::string colour;  // any SVG colour
  std::vector<double> x, y;
  bool points_only = false;  // markers without a line (events rather than a curve)
};

struct ChartPanel {
  std::string title;  // also the y axis' meaning and unit
  std::vector<ChartSeries> series;
  bool from_zero = true;  // the y axis starts at 0 (else at the smallest value)
};

namespace svg_detail {

// A round step giving about `ticks` intervals over `span`.
inline double nice_step(double span, int ticks) {
  const double raw = span / ticks;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (raw <= m * power) return m * power;
  return 10.0 * power;
}

inline std::string number(double v) {
  const double a = std::abs(v);
  if (a >= 1e4) return fmt::format("{:.0f}k", v / 1e3);
  if (a >= 10 || a == std::floor(a)) return fmt::format("{:.0f}", v);
  return fmt::format("{:.2g}", v);
}

}  // namespace svg_detail

// The panels, each `panel_height` px high, over x in [x_min, x_max], as one SVG document.
inline std::string svg_chart(const std::vector<ChartPanel>& panels, double x_min, double x_max,
                             const std::string& x_label, int width = 900, int panel_height = 200) {
  using svg_detail::nice_step;
  using svg_detail::number;
  const int left = 70, right = 200, top = 30, gap = 50, bottom = 40;
  const int plot_w = width - left - right;
  const int height = top + static_cast<int>(panels.size()) * (panel_height + gap) - gap + bottom;
  std::string out = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" font-family=\"sans-serif\" "
      "font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
      width, height);
  auto px = [&](double x) { return left + (x - x_min) / std::max(x_max - x_min, 1e-12) * plot_w; };
  for (std::size_t p = 0; p < panels.size(); ++p) {
    const ChartPanel& panel = panels[p];
    const int y0 = top + static_cast<int>(p) * (panel_height + gap);
    double lo = panel.from_zero ? 0.0 : 1e300, hi = -1e300;
    for (const ChartSeries& s : panel.series)
      for (const double v : s.y) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    if (!(hi > lo)) hi = lo + 1.0;
    const double step = nice_step(hi - lo, 4);
    lo = std::floor(lo / step) * step;
    hi = std::ceil(hi / step) * step;
    auto py = [&](double y) { return y0 + panel_height - (y - lo) / (hi - lo) * panel_height; };
    out += fmt::format("<text x=\"{}\" y=\"{}\" font-weight=\"bold\">{}</text>\n", left, y0 - 8, panel.title);
    for (double t = lo; t <= hi + step / 2; t += step)
      out += fmt::format(
          "<line x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#ddd\"/>"
          "<text x=\"{}\" y=\"{:.1f}\" text-anchor=\"end\">{}</text>\n",
          left, left + plot_w, py(t), py(t), left - 6, py(t) + 4, number(t));
    const double xstep = nice_step(x_max - x_min, 8);
    for (double t = std::ceil(x_min / xstep) * xstep; t <= x_max + xstep / 1e6; t += xstep)
      out += fmt::format("<text x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", px(t),
                         y0 + panel_height + 15, number(t));
    out += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#888\"/>\n",
                       left, y0, plot_w, panel_height);
    for (std::size_t k = 0; k < panel.series.size(); ++k) {
      const ChartSeries& s = panel.series[k];
      std::string path;
      for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
        if (s.points_only)
          out += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3.5\" fill=\"{}\"/>\n", px(s.x[i]),
                             py(s.y[i]), s.colour);
        else
          path += fmt::format("{}{:.1f},{:.1f}", path.empty() ? "M" : " L", px(s.x[i]), py(s.y[i]));
      }
      if (!path.empty())
        out +=
            fmt::format("<path d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\"/>\n", path, s.colour);
      const int ly = y0 + 14 + static_cast<int>(k) * 18;
      out += fmt::format(
          "<rect x=\"{}\" y=\"{}\" width=\"14\" height=\"4\" fill=\"{}\"/><text x=\"{}\" "
          "y=\"{}\">{}</text>\n",
          left + plot_w + 12, ly - 4, s.colour, left + plot_w + 32, ly, s.label);
    }
  }
  out += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n</svg>\n", left + plot_w / 2,
                     height - 8, x_label);
  return out;
}

}  // namespace lrd::bench
