// The paper's tables as bench_dynamic and `lrdslam sweep` write them (eval/paper_tables.h).
#include <gtest/gtest.h>

#include <string>

#include "lrd/eval/paper_tables.h"

namespace {

lrd::eval::ErrorStats stats(double rmse, double mean, double median, double std_dev) {
  lrd::eval::ErrorStats s;
  s.rmse = rmse;
  s.mean = mean;
  s.median = median;
  s.std_dev = std_dev;
  s.count = 10;
  return s;
}

lrd::eval::PaperTables walking_tables() {
  lrd::eval::PaperTables t({"walking_xyz", "walking_rpy"}, {"static", "full"});
  lrd::eval::PaperCell base;
  base.ate = stats(0.4, 0.3, 0.2, 0.1);
  base.rpe_trans = stats(0.5, 0.4, 0.3, 0.2);
  base.rpe_rot = stats(8.0, 7.0, 6.0, 1.0);
  base.time_mean_ms = 9.0;
  base.time_median_ms = 8.0;
  base.y_ms = 4.0;
  lrd::eval::PaperCell full = base;
  full.ate = stats(0.02, 0.015, 0.01, 0.005);
  full.rpe_trans = stats(0.05, 0.04, 0.03, 0.02);
  full.rpe_rot = stats(2.0, 1.0, 1.0, 0.5);
  full.y_ms = 5.0;
  t.set("walking_xyz", "static", base);
  t.set("walking_xyz", "full", full);
  t.set("walking_rpy", "full", full);  // no static run: no eta for this row
  return t;
}

TEST(PaperTables, ErrorTablesHoldEveryStatisticPerMode) {
  const std::string md = walking_tables().error_tables();
  EXPECT_NE(md.find("### Tables 4-5: ATE (m)"), std::string::npos);
  EXPECT_NE(md.find("### Table 6: RPE translation (m/s)"), std::string::npos);
  EXPECT_NE(md.find("### Table 7: RPE rotation (deg/s)"), std::string::npos);
  EXPECT_NE(md.find("| sequence | static RMSE | static mean | static median | static std | full RMSE |"),
            std::string::npos);
  EXPECT_NE(
      md.find("| walking_xyz | 0.4000 | 0.3000 | 0.2000 | 0.1000 | 0.0200 | 0.0150 | 0.0100 | 0.0050 |"),
      std::string::npos);
  EXPECT_NE(md.find("| walking_rpy | – | – | – | – | 0.0200 |"), std::string::npos);
}

TEST(PaperTables, ImprovementAndTimeAgainstTheirOwnY) {
  const lrd::eval::PaperTables t = walking_tables();
  const std::string eta = t.improvement_table();
  EXPECT_NE(eta.find("| walking_xyz | 95.0 / 90.0 / 75.0 |"), std::string::npos) << eta;
  EXPECT_NE(eta.find("| walking_rpy | – |"), std::string::npos) << eta;
  const std::string time = t.time_table();
  EXPECT_NE(
      time.find("| walking_xyz | 4.00 / 5.00 | 9.0 (2.25 Y) | 8.0 (2.00 Y) | 9.0 (1.80 Y) | 8.0 (1.60 Y) |"),
      std::string::npos)
      << time;
  lrd::eval::PaperTables no_static({"a"}, {"full"});
  EXPECT_EQ(no_static.improvement_table(), "");
}

}  // namespace
