#include "lrd/io/trajectory.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>

#include "lrd/util/atomic_file.h"
#include "lrd/util/error.h"

namespace lrd::io {
namespace {

// evaluate_rpe.py turns ',' and '\t' into ' ' and strips each token, so all of these separate.
bool is_separator(char c) {
  return c == ' ' || c == ',' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_separator(line[i])) ++i;
    const std::size_t begin = i;
    while (i < line.size() && !is_separator(line[i])) ++i;
    if (i > begin) fields.push_back(line.substr(begin, i - begin));
  }
  return fields;
}

// Python's float() also takes a leading '+', which std::from_chars does not.
bool parse_double(std::string_view token, double& value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  return ec == std::errc() && ptr == end;
}

std::string read_text(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) throw file_error(file, "no such trajectory file");
  if (std::filesystem::is_directory(file, ec))
    throw file_error(file, "is a directory, not a trajectory file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw file_error(file, "cannot open trajectory file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw file_error(file, "cannot read trajectory file");
  return std::move(text).str();
}

// transform44() of evaluate_rpe.py: a (near-)zero quaternion gives the identity rotation.
Eigen::Matrix3d rotation_from_quaternion(double qx, double qy, double qz, double qw) {
  const double eps = std::numeric_limits<double>::epsilon() * 4.0;
  const Eigen::Quaterniond q(qw, qx, qy, qz);
  if (q.squaredNorm() < eps) return Eigen::Matrix3d::Identity();
  return q.normalized().toRotationMatrix();
}

struct ParsedLine {
  StampedPose pose;
  std::size_t line = 0;
};

}  // namespace

Trajectory read_trajectory_tum(const std::filesystem::path& file) {
  const std::string text = read_text(file);
  std::vector<ParsedLine> parsed;
  std::size_t line_no = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    const std::string_view line(text.data() + pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    if (line.empty() || line.front() == '#') continue;
    const std::vector<std::string_view> fields = split_fields(line);
    if (fields.empty()) continue;
    if (fields.size() != 8) {
      throw line_error(
          file, line_no,
          fmt::format("expected 8 fields 'timestamp tx ty tz qx qy qz qw', found {}", fields.size()));
    }
    std::array<double, 8> v{};
    bool has_nan = false;
    for (std::size_t k = 0; k < v.size(); ++k) {
      if (!parse_double(fields[k], v[k])) {
        throw line_error(file, line_no, fmt::format("field {} '{}' is not a number", k + 1, fields[k]));
      }
      if (std::isinf(v[k])) throw line_error(file, line_no, fmt::format("field {} is infinite", k + 1));
      has_nan = has_nan || std::isnan(v[k]);
    }
    // evaluate_rpe.py drops these entries silently (all-zero quaternion) or with a warning (NaN).
    if (has_nan || (v[4] == 0.0 && v[5] == 0.0 && v[6] == 0.0 && v[7] == 0.0)) continue;
    ParsedLine entry;
    entry.line = line_no;
    entry.pose.timestamp = v[0];
    entry.pose.pose.linear() = rotation_from_quaternion(v[4], v[5], v[6], v[7]);
    entry.pose.pose.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    parsed.push_back(entry);
  }

  // Stable, so the error below names the later of two lines with the same timestamp.
  std::stable_sort(parsed.begin(), parsed.end(), [](const ParsedLine& a, const ParsedLine& b) {
    return a.pose.timestamp < b.pose.timestamp;
  });
  Trajectory trajectory;
  trajectory.reserve(parsed.size());
  for (std::size_t i = 0; i < parsed.size(); ++i) {
    if (i > 0 && parsed[i].pose.timestamp == parsed[i - 1].pose.timestamp) {
      const std::size_t first = std::min(parsed[i].line, parsed[i - 1].line);
      const std::size_t second = std::max(parsed[i].line, parsed[i - 1].line);
      throw line_error(
          file, second,
          fmt::format("duplicate timestamp {:.6f} (first seen on line {})", parsed[i].pose.timestamp, first));
    }
    trajectory.push_back(parsed[i].pose);
  }
  return trajectory;
}

void write_trajectory_tum(const std::filesystem::path& file, const Trajectory& trajectory) {
  util::AtomicFile file_out(file);
  std::ostream& out = file_out.stream();
  out << "# timestamp tx ty tz qx qy qz qw\n";
  for (const StampedPose& p : trajectory) {
    Eigen::Quaterniond q(p.pose.linear());
    q.normalize();
    if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // same rotation; keep qw >= 0 for readability
    const Eigen::Vector3d t = p.pose.translation();
    out << fmt::format("{:.6f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f}\n", p.timestamp, t.x(), t.y(),
                       t.z(), q.x(), q.y(), q.z(), q.w());
  }
  file_out.commit();
}

void write_trajectory_kitti(const std::filesystem::path& file, const Trajectory& trajectory) {
  util::AtomicFile out(file);
  for (const StampedPose& p : trajectory) {
    const Eigen::Matrix<double, 3, 4> m = p.pose.matrix().topRows<3>();
    std::string line;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) {
        if (!line.empty()) line += ' ';
        line += fmt::format("{:.9e}", m(r, c));
      }
    }
    line += '\n';
    out.write(line);
  }
  out.commit();
}

std::optional<Eigen::Isometry3d> pose_at(const Trajectory& trajectory, double t, double max_gap) {
  const auto after = std::lower_bound(trajectory.begin(), trajectory.end(), t,
                                      [](const StampedPose& p, double s) { return p.timestamp < s; });
  if (after != trajectory.end() && after->timestamp == t) return after->pose;
  if (after == trajectory.begin() || after == trajectory.end()) return std::nullopt;
  const StampedPose& before = *std::prev(after);
  const double gap = after->timestamp - before.timestamp;
  if (gap > max_gap) return std::nullopt;
  const double s = (t - before.timestamp) / gap;
  const Eigen::Quaterniond q0(before.pose.linear()), q1(after->pose.linear());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q0.slerp(s, q1).toRotationMatrix();
  pose.translation() = (1.0 - s) * before.pose.translation() + s * after->pose.translation();
  return pose;
}

}  // namespace lrd::io
