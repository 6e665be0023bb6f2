#include "lrd/io/tum_sequence.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>

#include "lrd/util/error.h"

namespace lrd::io {
namespace {

namespace fs = std::filesystem;

// One data line of a list file, split into fields.
struct Line {
  std::size_t number = 0;
  std::vector<std::string> fields;
};

// A "timestamp filename" item with where it came from, for error messages.
struct Stamped {
  double t = 0.0;
  std::string text;  // the timestamp as written
  std::string name;
  std::size_t line = 0;
};

// Like TUM's read_file_list: '#' comments and blank lines skipped, fields split on spaces,
// tabs and commas.
std::vector<Line> read_lines(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw file_error(file, "cannot open file");
  std::vector<Line> lines;
  std::string text;
  for (std::size_t n = 1; std::getline(in, text); ++n) {
    std::replace_if(
        text.begin(), text.end(), [](char c) { return c == ',' || c == '\t' || c == '\r'; }, ' ');
    std::istringstream ss(text);
    Line line{n, {}};
    for (std::string f; ss >> f;) line.fields.push_back(std::move(f));
    if (line.fields.empty() || line.fields[0][0] == '#') continue;
    lines.push_back(std::move(line));
  }
  return lines;
}

double parse_timestamp(const fs::path& file, std::size_t line, const std::string& text) {
  double t = 0.0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, t);
  if (ec != std::errc() || ptr != end || !std::isfinite(t)) {
    throw line_error(file, line, "malformed line: '" + text + "' is not a timestamp");
  }
  return t;
}

// Timestamps must increase strictly down the file (TUM lists do).
void check_order(const fs::path& file, const std::vector<Stamped>& items) {
  for (std::size_t i = 1; i < items.size(); ++i) {
    const Stamped& prev = items[i - 1];
    const Stamped& cur = items[i];
    if (cur.t == prev.t) {
      throw line_error(
          file, cur.line,
          "duplicate timestamp " + cur.text + " (also on line " + std::to_string(prev.line) + ")");
    }
    if (cur.t < prev.t) {
      throw line_error(file, cur.line,
                       "timestamps not sorted: " + cur.text + " comes after " + prev.text + " (line " +
                           std::to_string(prev.line) + ")");
    }
  }
}

std::vector<Stamped> read_list(const fs::path& file) {
  std::vector<Stamped> items;
  for (const Line& l : read_lines(file)) {
    if (l.fields.size() != 2) {
      throw line_error(file, l.number,
                       "malformed line: expected 'timestamp filename', got " +
                           std::to_string(l.fields.size()) + " fields");
    }
    items.push_back({parse_timestamp(file, l.number, l.fields[0]), l.fields[0], l.fields[1], l.number});
  }
  if (items.empty()) throw file_error(file, "no frames listed (empty sequence)");
  check_order(file, items);
  return items;
}

void check_image(const fs::path& list, std::size_t line, const fs::path& image) {
  std::error_code ec;
  if (!fs::is_regular_file(image, ec))
    throw line_error(list, line, "image file not found: " + image.string());
}

std::vector<FrameEntry> read_associations(const fs::path& dir, const fs::path& file) {
  std::vector<FrameEntry> entries;
  std::vector<Stamped> rgb;  // for the order check
  for (const Line& l : read_lines(file)) {
    if (l.fields.size() != 4) {
      throw line_error(file, l.number,
                       "malformed line: expected 't_rgb rgb_path t_depth depth_path', got " +
                           std::to_string(l.fields.size()) + " fields");
    }
    FrameEntry e;
    e.timestamp = parse_timestamp(file, l.number, l.fields[0]);
    e.rgb_path = dir / l.fields[1];
    e.depth_timestamp = parse_timestamp(file, l.number, l.fields[2]);
    e.depth_path = dir / l.fields[3];
    check_image(file, l.number, e.rgb_path);
    check_image(file, l.number, e.depth_path);
    rgb.push_back({e.timestamp, l.fields[0], l.fields[1], l.number});
    entries.push_back(std::move(e));
  }
  if (entries.empty()) throw file_error(file, "no frames listed (empty sequence)");
  check_order(file, rgb);
  return entries;
}

// associate.py: all pairs closer than max_dt, best first by (|dt|, t_rgb, t_depth), each image
// used once; returned in rgb order as (rgb index, depth index).
std::vector<std::pair<std::size_t, std::size_t>> associate(const std::vector<Stamped>& rgb,
                                                           const std::vector<Stamped>& depth, double max_dt) {
  std::vector<std::tuple<double, std::size_t, std::size_t>> candidates;
  auto less_t = [](const Stamped& s, double t) { return s.t < t; };
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    const double a = rgb[i].t;
    // Both lists are sorted: scan a window wider than max_dt, then apply the exact test.
    auto it = std::lower_bound(depth.begin(), depth.end(), a - 2.0 * max_dt, less_t);
    for (; it != depth.end() && it->t <= a + 2.0 * max_dt; ++it) {
      const double diff = std::abs(a - it->t);
      if (diff < max_dt) candidates.emplace_back(diff, i, static_cast<std::size_t>(it - depth.begin()));
    }
  }
  // Indices sort like the timestamps they index, which strictly increase.
  std::sort(candidates.begin(), candidates.end());
  std::vector<bool> rgb_used(rgb.size(), false), depth_used(depth.size(), false);
  std::vector<std::pair<std::size_t, std::size_t>> matches;
  for (const auto& [diff, i, j] : candidates) {
    if (rgb_used[i] || depth_used[j]) continue;
    rgb_used[i] = depth_used[j] = true;
    matches.emplace_back(i, j);
  }
  std::sort(matches.begin(), matches.end());
  return matches;
}

}  // namespace

TumSequence TumSequence::open(const fs::path& dir, double max_dt) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) throw file_error(dir, "sequence folder not found");
  if (!fs::is_directory(dir, ec))
    throw file_error(dir, "not a folder (expected a TUM RGB-D sequence folder)");
  if (!(max_dt > 0.0)) throw file_error(dir, "association max_dt must be > 0, got " + std::to_string(max_dt));

  TumSequence seq;
  seq.dir_ = dir;
  const fs::path associations = dir / "associations.txt";
  // A list that is there but no file (a folder, a dangling link) is a broken sequence, not an
  // absent list: say so instead of silently reading another.
  for (const char* list : {"associations.txt", "rgb.txt", "depth.txt", "groundtruth.txt"}) {
    const fs::path f = dir / list;
    if ((fs::exists(f, ec) || fs::is_symlink(f, ec)) && !fs::is_regular_file(f, ec))
      throw file_error(f, "not a readable regular file");
  }
  if (fs::is_regular_file(associations, ec)) {
    seq.entries_ = read_associations(dir, associations);
  } else {
    const fs::path rgb_list = dir / "rgb.txt";
    const fs::path depth_list = dir / "depth.txt";
    for (const fs::path& f : {rgb_list, depth_list}) {
      if (!fs::is_regular_file(f, ec))
        throw file_error(f, "file not found (a TUM sequence needs rgb.txt and depth.txt)");
    }
    const std::vector<Stamped> rgb = read_list(rgb_list);
    const std::vector<Stamped> depth = read_list(depth_list);
    const auto matches = associate(rgb, depth, max_dt);
    if (matches.empty()) {
      std::ostringstream dt;
      dt << max_dt;
      throw file_error(rgb_list, "empty sequence: none of the " + std::to_string(rgb.size()) +
                                     " rgb images has a depth image in depth.txt within " + dt.str() + " s");
    }
    seq.entries_.reserve(matches.size());
    for (const auto& [i, j] : matches) {
      FrameEntry e{rgb[i].t, dir / rgb[i].name, depth[j].t, dir / depth[j].name};
      check_image(rgb_list, rgb[i].line, e.rgb_path);
      check_image(depth_list, depth[j].line, e.depth_path);
      seq.entries_.push_back(std::move(e));
    }
  }
  const fs::path gt = dir / "groundtruth.txt";
  if (fs::is_regular_file(gt, ec)) seq.groundtruth_ = gt;
  return seq;
}

RgbdFrame TumSequence::load_rgbd(std::size_t i, double depth_factor) const {
  if (i >= entries_.size()) {
    throw file_error(dir_, "frame index " + std::to_string(i) + " out of range (sequence has " +
                               std::to_string(entries_.size()) + " frames)");
  }
  return load_rgbd_frame(entries_[i], i, depth_factor);
}

std::vector<std::pair<std::size_t, std::size_t>> associate_timestamps(const std::vector<double>& rgb,
                                                                      const std::vector<double>& depth,
                                                                      double max_dt) {
  const auto stamped = [](const std::vector<double>& t) {
    std::vector<Stamped> s(t.size());
    for (std::size_t i = 0; i < t.size(); ++i) s[i].t = t[i];
    return s;
  };
  return associate(stamped(rgb), stamped(depth), max_dt);
}

std::optional<Trajectory> TumSequence::ground_truth() const {
  if (!groundtruth_) return std::nullopt;
  return read_trajectory_tum(*groundtruth_);
}

std::string TumSequence::ground_truth_origin() const {
  return groundtruth_ ? groundtruth_->string() : std::string();
}

}  // namespace lrd::io
