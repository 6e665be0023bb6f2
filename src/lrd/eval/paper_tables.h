#pragma once
// The paper's result tables as Markdown, for every tool that fills them (bench_dynamic from its
// runs, `lrdslam sweep` from the medians over repeats): Tables 4-5, 6 and 7 (ATE, RPE translation,
// RPE rotation: RMSE / mean / median / std per sequence and mode), the improvement rate eta over
// `static` (Eq. 12), and Table 10 (time per frame, ms and multiples of the yardstick Y).
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lrd/eval/statistics.h"

namespace lrd::eval {

// One sequence in one mode: a run, or the median of a cell's repeats.
struct PaperCell {
  std::optional<ErrorStats> ate, rpe_trans, rpe_rot;  // nullopt: no ground truth, or no run
  std::optional<double> time_mean_ms, time_median_ms;
  std::optional<double> y_ms;  // the yardstick the times are divided by
};

class PaperTables {
 public:
  PaperTables(std::vector<std::string> rows, std::vector<std::string> modes)
      : rows_(std::move(rows)), modes_(std::move(modes)) {}
  void set(const std::string& row, const std::string& mode, PaperCell cell) {
    cells_[{row, mode}] = std::move(cell);
  }

  // Tables 4-5, 6 and 7, one after the other.
  [[nodiscard]] std::string error_tables() const;
  // eta = (static - mode) / static of the ATE, RPE translation and RPE rotation RMSEs, in %; empty
  // without a `static` mode.
  [[nodiscard]] std::string improvement_table() const;
  // Table 10: mean and median time per frame per mode, ms and (Y); the Y column lists each mode's.
  [[nodiscard]] std::string time_table() const;

 private:
  [[nodiscard]] const PaperCell* find(const std::string& row, const std::string& mode) const;
  [[nodiscard]] std::string error_table(const std::string& title,
                                        const std::optional<ErrorStats> PaperCell::*field) const;

  std::vector<std::string> rows_, modes_;
  std::map<std::pair<std::string, std::string>, PaperCell> cells_;
};

}  // namespace lrd::eval
