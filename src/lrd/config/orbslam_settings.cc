#include "lrd/config/orbslam_settings.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <map>
#include <opencv2/core/persistence.hpp>
#include <optional>
#include <string>

#include "lrd/config/plausibility.h"
#include "lrd/util/error.h"

namespace lrd::config {
namespace {

// OpenCV's messages may span lines; lrd::Error messages must not.
std::string one_line(std::string s) {
  for (char& c : s) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// A parse error says "NAME(LINE): problem"; OpenCV 4.6 puts that in e.func (and the parser
// function's name in e.err), later versions may swap them back, so look in both.
Error parse_error(const std::filesystem::path& file, const cv::Exception& e) {
  for (const std::string& text : {e.func, e.err}) {
    const auto close = text.find("): ");
    const auto open = close == std::string::npos ? std::string::npos : text.rfind('(', close);
    std::size_t line = 0;
    if (open == std::string::npos) continue;
    const auto [ptr, ec] = std::from_chars(text.data() + open + 1, text.data() + close, line);
    if (ec != std::errc() || ptr != text.data() + close) continue;
    return line_error(file, line, "cannot parse settings file: " + one_line(text.substr(close + 3)));
  }
  return file_error(file, "cannot parse settings file: " + one_line(e.err));
}

// A settings file is a map of keys: each top-level line (not blank, not a comment, not indented
// under a key) is "KEY: ..." or a YAML directive or document marker. Checked before OpenCV parses
// the file, because OpenCV 4.6's parser never returns on some other top levels (a sequence item
// followed by a plain line; a NUL byte, after which it parses the rest of the line as a new one:
// both found by fuzzing).
void check_top_level(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    // OpenCV reads lines as C strings: text after a NUL is parsed as if a line began there.
    if (line.find('\0') != std::string::npos) throw line_error(file, n, "not a settings file: a NUL byte");
    if (line.empty() || line[0] == '#' || line[0] == ' ' || line[0] == '\t' || line[0] == '%') continue;
    if (line.rfind("---", 0) == 0 && line.find_first_not_of('-') == std::string::npos) continue;
    if (line == "...") continue;
    const std::size_t colon = line.find(':');
    if (line[0] == '-' || colon == std::string::npos || colon == 0)
      throw line_error(file, n, "not a settings file: expected KEY: VALUE at the top level");
  }
}

class SettingsFile {
 public:
  explicit SettingsFile(std::filesystem::path file) : file_(std::move(file)) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file_, ec)) throw file_error(file_, "settings file not found");
    check_top_level(file_);
    try {
      // FORMAT_YAML: parse as YAML whatever the extension is.
      fs_.open(file_.string(), cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML);
    } catch (const cv::Exception& e) {
      throw parse_error(file_, e);
    }
    if (!fs_.isOpened()) throw file_error(file_, "cannot open settings file");
    // OpenCV asserts (an exception of its own) when a key is looked up in anything but a map.
    if (!fs_.root().isMap())
      throw file_error(file_, "not a settings file: its top level is not a map of keys");
  }

  [[nodiscard]] std::optional<double> number(const std::string& key) const {
    const cv::FileNode node = fs_[key];
    if (node.empty() || node.isNone()) return std::nullopt;
    if (!node.isInt() && !node.isReal()) throw file_error(file_, "key '" + key + "' must be a number");
    const double v = node.real();
    if (!std::isfinite(v)) throw file_error(file_, "key '" + key + "' must be finite");
    return v;
  }

  [[nodiscard]] double required(const std::string& key) const {
    const auto v = number(key);
    if (!v) throw file_error(file_, "missing required key '" + key + "'");
    return *v;
  }

  // Value of the first of `keys` present; at least one is required.
  [[nodiscard]] double first_of(std::initializer_list<const char*> keys) const {
    for (const char* k : keys) {
      if (const auto v = number(k)) return *v;
    }
    std::string names;
    for (const char* k : keys) names += (names.empty() ? "'" : " or '") + std::string(k) + "'";
    throw file_error(file_, "missing required key " + names);
  }

  [[nodiscard]] double get(const std::string& key, double fallback) const {
    return number(key).value_or(fallback);
  }

  [[nodiscard]] int get_int(const std::string& key, int fallback) const {
    const double v = get(key, fallback);
    if (v != std::floor(v) || std::abs(v) > 1e9)
      throw file_error(file_, "key '" + key + "' must be an integer");
    return static_cast<int>(v);
  }

  [[nodiscard]] std::optional<std::string> string(const std::string& key) const {
    const cv::FileNode node = fs_[key];
    if (node.empty() || node.isNone()) return std::nullopt;
    if (node.isString()) return node.string();
    if (node.isInt() || node.isReal()) return cv::format("%g", node.real());
    throw file_error(file_, "key '" + key + "' must be a string");
  }

  void check(bool ok, const std::string& key, const std::string& what) const {
    if (!ok) throw file_error(file_, "key '" + key + "' " + what);
  }

  [[nodiscard]] const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
  cv::FileStorage fs_;
};

features::OrbParams read_orb(const SettingsFile& f) {
  features::OrbParams orb;
  orb.n_features = f.get_int("ORBextractor.nFeatures", orb.n_features);
  orb.scale_factor = static_cast<float>(f.get("ORBextractor.scaleFactor", orb.scale_factor));
  orb.n_levels = f.get_int("ORBextractor.nLevels", orb.n_levels);
  orb.ini_th_fast = f.get_int("ORBextractor.iniThFAST", orb.ini_th_fast);
  orb.min_th_fast = f.get_int("ORBextractor.minThFAST", orb.min_th_fast);
  f.check(orb.n_features > 0, "ORBextractor.nFeatures", "must be > 0");
  f.check(orb.scale_factor > 1.0f, "ORBextractor.scaleFactor", "must be > 1");
  f.check(orb.n_levels >= 1, "ORBextractor.nLevels", "must be >= 1");
  f.check(orb.ini_th_fast > 0, "ORBextractor.iniThFAST", "must be > 0");
  f.check(orb.min_th_fast > 0, "ORBextractor.minThFAST", "must be > 0");
  if (const auto bad = implausible_orb(orb)) {
    const std::map<std::string, std::string> key = {{"n_features", "ORBextractor.nFeatures"},
                                                    {"scale_factor", "ORBextractor.scaleFactor"},
                                                    {"n_levels", "ORBextractor.nLevels"},
                                                    {"ini_th_fast", "ORBextractor.iniThFAST"},
                                                    {"min_th_fast", "ORBextractor.minThFAST"}};
    f.check(false, key.at(bad->field), bad->problem);
  }
  return orb;
}

}  // namespace

Settings read_orbslam_settings(const std::filesystem::path& file) {
  const SettingsFile f(file);
  Settings s;
  camera::PinholeCamera& cam = s.camera;
  cam.name = file.stem().string();

  const auto version = f.string("File.version");
  const bool v3 = version.has_value();
  if (v3) {
    // An unquoted 1.0 is read as a number and printed as "1".
    f.check(*version == "1.0" || *version == "1", "File.version",
            "is '" + *version + "', only \"1.0\" is supported");
    const auto type = f.string("Camera.type").value_or("PinHole");
    f.check(type == "PinHole", "Camera.type", "is '" + type + "', only \"PinHole\" is supported");
  }
  const std::string c = v3 ? "Camera1." : "Camera.";
  cam.fx = f.required(c + "fx");
  cam.fy = f.required(c + "fy");
  cam.cx = f.required(c + "cx");
  cam.cy = f.required(c + "cy");
  cam.distortion.k1 = f.get(c + "k1", 0.0);
  cam.distortion.k2 = f.get(c + "k2", 0.0);
  cam.distortion.p1 = f.get(c + "p1", 0.0);
  cam.distortion.p2 = f.get(c + "p2", 0.0);
  cam.distortion.k3 = f.get(c + "k3", 0.0);
  f.check(cam.fx > 0.0, c + "fx", "must be > 0");
  f.check(cam.fy > 0.0, c + "fy", "must be > 0");

  // ORB-SLAM3 requires the image size; ORB-SLAM2's TUM files do not carry it.
  if (v3) {
    (void)f.required("Camera.width");
    (void)f.required("Camera.height");
  }
  cam.width = f.get_int("Camera.width", cam.width);
  cam.height = f.get_int("Camera.height", cam.height);
  f.check(cam.width > 0, "Camera.width", "must be > 0");
  f.check(cam.height > 0, "Camera.height", "must be > 0");
  cam.fps = f.get("Camera.fps", cam.fps);
  f.check(cam.fps > 0.0, "Camera.fps", "must be > 0");
  cam.rgb_order = f.get_int("Camera.RGB", 1) != 0;
  // Not an ORB-SLAM key: lrd-slam's rolling-shutter readout (seconds; absent: a global shutter).
  cam.readout_time = f.get("Camera.readoutTime", 0.0);

  if (v3) {
    // ORB-SLAM3 stores the baseline in metres; bf = b * fx as ORB-SLAM3 computes it.
    if (const auto b = f.number("Stereo.b")) {
      cam.bf = *b * cam.fx;
    } else {
      cam.bf = f.first_of({"Stereo.b", "Camera.bf"});
    }
    cam.th_depth = f.first_of({"Stereo.ThDepth", "ThDepth"});
    cam.depth_map_factor = f.first_of({"RGBD.DepthMapFactor", "DepthMapFactor"});
  } else {
    cam.bf = f.required("Camera.bf");
    cam.th_depth = f.required("ThDepth");
    cam.depth_map_factor = f.required("DepthMapFactor");
  }
  f.check(cam.bf > 0.0, v3 ? "Stereo.b" : "Camera.bf", "must be > 0");
  f.check(cam.th_depth > 0.0, v3 ? "Stereo.ThDepth" : "ThDepth", "must be > 0");
  f.check(cam.depth_map_factor > 0.0, v3 ? "RGBD.DepthMapFactor" : "DepthMapFactor", "must be > 0");
  if (const auto bad = implausible_camera(cam)) {
    const std::map<std::string, std::string> key = {
        {"width", "Camera.width"},
        {"height", "Camera.height"},
        {"fps", "Camera.fps"},
        {"bf", v3 ? "Stereo.b" : "Camera.bf"},
        {"th_depth", v3 ? "Stereo.ThDepth" : "ThDepth"},
        {"depth_map_factor", v3 ? "RGBD.DepthMapFactor" : "DepthMapFactor"},
        {"readout_time", "Camera.readoutTime"}};
    const auto it = key.find(bad->field);
    f.check(false, it != key.end() ? it->second : c + bad->field, bad->problem);
  }

  s.orb = read_orb(f);
  return s;
}

}  // namespace lrd::config
