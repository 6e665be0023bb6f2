#include "lrd/dense/ply_io.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <fstream>
#include <opencv2/core/saturate.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "lrd/util/atomic_file.h"
#include "lrd/util/error.h"

namespace lrd::dense {

namespace fs = std::filesystem;

void write_ply(const fs::path& file, const PointCloud& cloud) {
  util::AtomicFile file_out(file);
  std::ostream& out = file_out.stream();
  const bool coloured = cloud.colours.size() == cloud.points.size();
  out << "ply\nformat binary_little_endian 1.0\ncomment written by lrd-slam\nelement vertex " << cloud.size()
      << "\nproperty float x\nproperty float y\nproperty float z\n";
  if (coloured) out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  out << "end_header\n";
  // The floats go out as they are in memory, point by point through the stream's buffer (a dense
  // map is not copied whole).
  static_assert(std::endian::native == std::endian::little, "write_ply assumes a little-endian machine");
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    std::array<char, 15> row{};
    std::memcpy(row.data(), cloud.points[i].data(), 12);
    if (coloured) {
      const cv::Vec3b& c = cloud.colours[i];
      row[12] = static_cast<char>(c[2]);
      row[13] = static_cast<char>(c[1]);
      row[14] = static_cast<char>(c[0]);
    }
    out.write(row.data(), coloured ? 15 : 12);
  }
  file_out.commit();
}

namespace {

struct Property {
  std::string name, type;
  [[nodiscard]] int size() const {
    if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
    if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
    if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" ||
        type == "float32")
      return 4;
    if (type == "double" || type == "float64") return 8;
    return 0;
  }
};

struct Element {
  std::string name;
  std::size_t count = 0;
  std::vector<Property> properties;
  bool has_list = false;
};

double read_binary(const char* p, const std::string& type) {
  if (type == "float" || type == "float32") {
    float f;
    std::memcpy(&f, p, 4);
    return f;
  }
  if (type == "double" || type == "float64") {
    double d;
    std::memcpy(&d, p, 8);
    return d;
  }
  if (type == "uchar" || type == "uint8") return static_cast<unsigned char>(*p);
  if (type == "char" || type == "int8") return static_cast<signed char>(*p);
  if (type == "ushort" || type == "uint16") {
    std::uint16_t v;
    std::memcpy(&v, p, 2);
    return v;
  }
  if (type == "short" || type == "int16") {
    std::int16_t v;
    std::memcpy(&v, p, 2);
    return v;
  }
  if (type == "uint" || type == "uint32") {
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
  }
  std::int32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

}  // namespace

PointCloud read_ply(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw file_error(file, "cannot open (missing or unreadable)");
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) throw file_error(file, "not a PLY file");
  std::string format;
  std::vector<Element> elements;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "format") {
      ls >> format;
    } else if (word == "element") {
      Element e;
      long long count = -1;
      ls >> e.name >> count;
      if (!ls || count < 0) throw file_error(file, "bad element line '" + line + "'");
      e.count = static_cast<std::size_t>(count);
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) throw file_error(file, "property before any element");
      std::string type;
      ls >> type;
      if (type == "list") {
        elements.back().has_list = true;
        continue;
      }
      Property p;
      p.type = type;
      ls >> p.name;
      if (p.size() == 0) throw file_error(file, "unsupported property type '" + type + "'");
      elements.back().properties.push_back(p);
    } else if (word == "end_header") {
      break;
    }
  }
  if (format != "binary_little_endian" && format != "ascii")
    throw file_error(file, "unsupported PLY format '" + format + "' (binary_little_endian or ascii)");
  PointCloud cloud;
  bool found = false;
  const std::streampos body = in.tellg();
  in.seekg(0, std::ios::end);
  const auto remaining = static_cast<std::size_t>(in.tellg() - body);
  in.seekg(body);
  for (const Element& e : elements) {
    if (e.name != "vertex") {
      if (e.count == 0) continue;
      // Elements after the vertices (faces) are not needed; ones before them cannot be skipped safely.
      throw file_error(file, "element '" + e.name + "' before the vertices");
    }
    found = true;
    if (e.has_list) throw file_error(file, "list properties on vertices are not supported");
    int ix = -1, iy = -1, iz = -1, ir = -1, ig = -1, ib = -1;
    std::vector<int> offset;
    int stride = 0;
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      const std::string& n = e.properties[k].name;
      const int ik = static_cast<int>(k);
      if (n == "x") ix = ik;
      if (n == "y") iy = ik;
      if (n == "z") iz = ik;
      if (n == "red") ir = ik;
      if (n == "green") ig = ik;
      if (n == "blue") ib = ik;
      offset.push_back(stride);
      stride += e.properties[k].size();
    }
    if (ix < 0 || iy < 0 || iz < 0) throw file_error(file, "vertices have no x, y, z");
    const bool coloured = ir >= 0 && ig >= 0 && ib >= 0;
    // Binary: the count must fit the bytes there are (before allocating for it); ASCII: at
    // least two bytes per number.
    const std::size_t min_bytes =
        format == "ascii" ? 2 * e.properties.size() : static_cast<std::size_t>(stride);
    if (e.count > remaining / std::max<std::size_t>(min_bytes, 1))
      throw file_error(
          file, "truncated: " + std::to_string(e.count) + " vertices announced, the file is too short");
    cloud.points.resize(e.count);
    if (coloured) cloud.colours.resize(e.count);
    std::vector<char> row(static_cast<std::size_t>(stride));
    std::vector<double> values(e.properties.size());
    for (std::size_t i = 0; i < e.count; ++i) {
      if (format == "ascii") {
        for (double& v : values)
          if (!(in >> v))
            throw file_error(
                file, "truncated: " + std::to_string(i) + " of " + std::to_string(e.count) + " vertices");
      } else {
        if (!in.read(row.data(), stride))
          throw file_error(
              file, "truncated: " + std::to_string(i) + " of " + std::to_string(e.count) + " vertices");
        for (std::size_t k = 0; k < values.size(); ++k)
          values[k] = read_binary(row.data() + offset[k], e.properties[k].type);
      }
      cloud.points[i] = Eigen::Vector3f(static_cast<float>(values[static_cast<std::size_t>(ix)]),
                                        static_cast<float>(values[static_cast<std::size_t>(iy)]),
                                        static_cast<float>(values[static_cast<std::size_t>(iz)]));
      if (coloured)
        cloud.colours[i] = cv::Vec3b(cv::saturate_cast<uchar>(values[static_cast<std::size_t>(ib)]),
                                     cv::saturate_cast<uchar>(values[static_cast<std::size_t>(ig)]),
                                     cv::saturate_cast<uchar>(values[static_cast<std::size_t>(ir)]));
    }
    break;
  }
  if (!found) throw file_error(file, "no vertex element");
  return cloud;
}

}  // namespace lrd::dense
