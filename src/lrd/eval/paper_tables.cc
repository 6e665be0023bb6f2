#include "lrd/eval/paper_tables.h"

#include <fmt/format.h>

#include "lrd/eval/improvement.h"

namespace lrd::eval {

namespace {

constexpr const char* kNone = "–";

std::string header(const std::vector<std::string>& first, const std::vector<std::string>& columns) {
  std::string md = "|";
  for (const std::string& c : first) md += fmt::format(" {} |", c);
  for (const std::string& c : columns) md += fmt::format(" {} |", c);
  md += "\n|";
  for (std::size_t i = 0; i < first.size() + columns.size(); ++i) md += "---|";
  return md + "\n";
}

}  // namespace

const PaperCell* PaperTables::find(const std::string& row, const std::string& mode) const {
  const auto it = cells_.find({row, mode});
  return it == cells_.end() ? nullptr : &it->second;
}

std::string PaperTables::error_table(const std::string& title,
                                     const std::optional<ErrorStats> PaperCell::*field) const {
  std::vector<std::string> columns;
  for (const std::string& m : modes_)
    for (const char* stat : {" RMSE", " mean", " median", " std"}) columns.push_back(m + stat);
  std::string md = fmt::format("### {}\n\n", title) + header({"sequence"}, columns);
  for (const std::string& row : rows_) {
    md += fmt::format("| {} |", row);
    for (const std::string& m : modes_) {
      const PaperCell* c = find(row, m);
      if (c == nullptr || !(c->*field)) {
        md += fmt::format(" {0} | {0} | {0} | {0} |", kNone);
        continue;
      }
      const ErrorStats& s = *(c->*field);
      md += fmt::format(" {:.4f} | {:.4f} | {:.4f} | {:.4f} |", s.rmse, s.mean, s.median, s.std_dev);
    }
    md += "\n";
  }
  return md + "\n";
}

std::string PaperTables::error_tables() const {
  return error_table("Tables 4-5: ATE (m)", &PaperCell::ate) +
         error_table("Table 6: RPE translation (m/s)", &PaperCell::rpe_trans) +
         error_table("Table 7: RPE rotation (deg/s)", &PaperCell::rpe_rot);
}

std::string PaperTables::improvement_table() const {
  std::vector<std::string> others;
  for (const std::string& m : modes_)
    if (m != "static") others.push_back(m);
  if (others.size() == modes_.size() || others.empty()) return "";
  std::string md =
      "### Improvement rate eta over `static` (ATE RMSE / RPE trans RMSE / RPE rot RMSE, %)\n\n" +
      header({"sequence"}, others);
  for (const std::string& row : rows_) {
    md += fmt::format("| {} |", row);
    const PaperCell* base = find(row, "static");
    for (const std::string& m : others) {
      const PaperCell* c = find(row, m);
      if (base == nullptr || c == nullptr || !base->ate || !c->ate || !base->rpe_trans || !c->rpe_trans) {
        md += fmt::format(" {} |", kNone);
        continue;
      }
      md += fmt::format(" {:.1f} / {:.1f} / {:.1f} |", improvement_percent(base->ate->rmse, c->ate->rmse),
                        improvement_percent(base->rpe_trans->rmse, c->rpe_trans->rmse),
                        improvement_percent(base->rpe_rot->rmse, c->rpe_rot->rmse));
    }
    md += "\n";
  }
  return md + "\n";
}

std::string PaperTables::time_table() const {
  std::vector<std::string> columns;
  for (const std::string& m : modes_) {
    columns.push_back(m + " mean");
    columns.push_back(m + " median");
  }
  std::string md = "### Table 10: time per frame (ms; multiples of each run's Y)\n\n" +
                   header({"sequence", "Y (ms)"}, columns);
  const auto in_y = [](const std::optional<double>& ms, const std::optional<double>& y) {
    if (!ms) return std::string(kNone);
    return y && *y > 0.0 ? fmt::format("{:.1f} ({:.2f} Y)", *ms, *ms / *y) : fmt::format("{:.1f}", *ms);
  };
  for (const std::string& row : rows_) {
    std::string ys, times;
    for (const std::string& m : modes_) {
      const PaperCell* c = find(row, m);
      ys += fmt::format("{}{}", ys.empty() ? "" : " / ",
                        c != nullptr && c->y_ms ? fmt::format("{:.2f}", *c->y_ms) : std::string(kNone));
      times += c == nullptr ? fmt::format(" {0} | {0} |", kNone)
                            : fmt::format(" {} | {} |", in_y(c->time_mean_ms, c->y_ms),
                                          in_y(c->time_median_ms, c->y_ms));
    }
    md += fmt::format("| {} | {} |{}\n", row, ys, times);
  }
  return md + "\n";
}

}  // namespace lrd::eval
