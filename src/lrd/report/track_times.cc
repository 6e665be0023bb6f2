#include "lrd/report/track_times.h"

#include <charconv>
#include <fstream>
#include <sstream>

#include "lrd/util/error.h"

namespace lrd::report {
namespace {

constexpr std::string_view kHeader = "# frame timestamp extraction_ms segmentation_ms";
constexpr std::size_t kFields = 15;

template <typename T>
T parse(const std::string& field, const std::filesystem::path& file, std::size_t line, const char* what) {
  T value{};
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (ec != std::errc() || end != field.data() + field.size())
    throw line_error(file, line, std::string("bad ") + what + " '" + field + "'");
  return value;
}

FrameTimes parse_row(const std::vector<std::string>& f, const std::filesystem::path& file, std::size_t line) {
  FrameTimes t;
  t.index = parse<long>(f[0], file, line, "frame");
  t.timestamp = parse<double>(f[1], file, line, "timestamp");
  for (std::size_t i = 2; i < 9; ++i) t.stage_ms.push_back(parse<double>(f[i], file, line, "time"));
  t.total_ms = parse<double>(f[9], file, line, "total time");
  t.state = f[10];
  t.inliers = parse<int>(f[11], file, line, "inlier count");
  t.mask_frame = parse<long>(f[12], file, line, "mask frame");
  t.mask_age = parse<long>(f[13], file, line, "mask age");
  t.dynamic_keypoints = parse<int>(f[14], file, line, "dynamic keypoint count");
  return t;
}

}  // namespace

const std::vector<std::string>& stage_names() {
  static const std::vector<std::string> names = {"extraction", "segmentation", "mask_wait", "geometry",
                                                 "tracking",   "waiting",      "mapping"};
  return names;
}

std::vector<FrameTimes> read_track_times(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw file_error(file, "cannot read (not found?)");
  std::string text;
  if (!std::getline(in, text) || text.rfind(kHeader, 0) != 0)
    throw file_error(file,
                     "not a track_times.txt (its first line is not '" + std::string(kHeader) + " ...')");
  std::vector<FrameTimes> rows;
  for (std::size_t line = 2; std::getline(in, text); ++line) {
    if (text.empty() || text[0] == '#') continue;
    std::istringstream fields(text);
    std::vector<std::string> f;
    for (std::string s; fields >> s;) f.push_back(s);
    if (f.size() != kFields)
      throw line_error(file, line,
                       "expected " + std::to_string(kFields) + " fields, got " + std::to_string(f.size()));
    rows.push_back(parse_row(f, file, line));
  }
  return rows;
}

}  // namespace lrd::report
