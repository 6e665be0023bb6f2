// The HTML report's parts that need no run (docs/report.md): base64 for the inlined images and the
// track_times.txt reader. tests/python/test_cli_report.py and test_report_browser.py check pages.
#include <gtest/gtest.h>

#include <string>

#include "error_of.h"
#include "lrd/report/html_page.h"
#include "lrd/report/track_times.h"
#include "temp_dir.h"

namespace {

using lrd::test::error_of;
using lrd::test::TempDir;

const std::string kHeader =
    "# frame timestamp extraction_ms segmentation_ms mask_wait_ms geometry_ms tracking_ms waiting_ms "
    "mapping_ms total_ms state inliers mask_frame mask_age dynamic_kps\n";

TEST(Report, Base64MatchesRfc4648) {
  EXPECT_EQ(lrd::report::base64(""), "");
  EXPECT_EQ(lrd::report::base64("f"), "Zg==");
  EXPECT_EQ(lrd::report::base64("fo"), "Zm8=");
  EXPECT_EQ(lrd::report::base64("foo"), "Zm9v");
  EXPECT_EQ(lrd::report::base64("foob"), "Zm9vYg==");
  EXPECT_EQ(lrd::report::base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(lrd::report::base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(lrd::report::base64(std::string("\xff\xfe\x00", 3)), "//4A");
}

TEST(Report, TrackTimesReadBack) {
  TempDir dir("report");
  const auto file = dir.write("track_times.txt", kHeader +
                                                     "0 1.500000 10.000 30.000 0.000 1.000 2.500 0.000 0.000 "
                                                     "13.500 not-initialized 0 -1 -1 0\n"
                                                     "1 1.533333 9.000 31.000 0.500 1.000 3.000 0.250 4.000 "
                                                     "17.750 ok 312 0 1 17\n");
  const auto rows = lrd::report::read_track_times(file);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].index, 1);
  EXPECT_DOUBLE_EQ(rows[1].timestamp, 1.533333);
  ASSERT_EQ(rows[1].stage_ms.size(), lrd::report::stage_names().size());
  EXPECT_DOUBLE_EQ(rows[1].stage_ms[6], 4.0);  // mapping
  EXPECT_DOUBLE_EQ(rows[1].total_ms, 17.75);
  EXPECT_EQ(rows[0].state, "not-initialized");
  EXPECT_EQ(rows[1].inliers, 312);
  EXPECT_EQ(rows[0].mask_frame, -1);
  EXPECT_EQ(rows[1].mask_age, 1);
  EXPECT_EQ(rows[1].dynamic_keypoints, 17);
}

TEST(Report, BadTrackTimesNameTheFileAndLine) {
  TempDir dir("report");
  const auto missing = dir.path() / "none.txt";
  EXPECT_EQ(error_of([&] { (void)lrd::report::read_track_times(missing); }),
            missing.string() + ": cannot read (not found?)");
  const auto other = dir.write("other.txt", "# timestamp tx ty tz qx qy qz qw\n");
  EXPECT_NE(error_of([&] {
              (void)lrd::report::read_track_times(other);
            }).find(other.string() + ": not a track_times.txt"),
            std::string::npos);
  const auto bad = dir.write("bad.txt", kHeader + "0 1.5 x 0 0 0 0 0 0 0 ok 0 -1 -1 0\n");
  EXPECT_EQ(error_of([&] { (void)lrd::report::read_track_times(bad); }), bad.string() + ":2: bad time 'x'");
}

}  // namespace
