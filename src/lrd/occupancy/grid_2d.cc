#include "lrd/occupancy/grid_2d.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "lrd/io/image_file.h"
#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"

namespace lrd::occupancy {

namespace fs = std::filesystem;

bool Grid2d::cell_of(const Eigen::Vector2d& xy, int& x, int& y) const {
  x = static_cast<int>(std::floor((xy.x() - origin.x()) / resolution));
  y = static_cast<int>(std::floor((xy.y() - origin.y()) / resolution));
  return x >= 0 && y >= 0 && x < width && y < height;
}

std::size_t Grid2d::count(std::int8_t value) const {
  return static_cast<std::size_t>(std::count(cells.begin(), cells.end(), value));
}

Grid2d project_to_grid(const OccupancyMap& map, const FloorFrame& floor, double min_height, double max_height,
                       bool filter_speckles) {
  Grid2d g;
  g.resolution = map.resolution();
  g.floor = floor;
  g.min_height = min_height;
  g.max_height = max_height;
  struct Cell {
    long x, y;
    bool occupied;
  };
  std::vector<Cell> band;
  long x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  map.visit([&](const Eigen::Vector3d& centre, bool occupied) {
    const Eigen::Vector3d q = floor.to_floor(centre);
    if (q.z() < min_height || q.z() > max_height) return;
    if (occupied && filter_speckles && !map.has_occupied_neighbour(centre)) return;
    const Cell c{std::lround(std::floor(q.x() / g.resolution)), std::lround(std::floor(q.y() / g.resolution)),
                 occupied};
    if (band.empty()) {
      x0 = x1 = c.x;
      y0 = y1 = c.y;
    }
    x0 = std::min(x0, c.x), x1 = std::max(x1, c.x), y0 = std::min(y0, c.y), y1 = std::max(y1, c.y);
    band.push_back(c);
  });
  if (band.empty()) return g;
  g.width = static_cast<int>(x1 - x0 + 1);
  g.height = static_cast<int>(y1 - y0 + 1);
  g.origin = Eigen::Vector2d(static_cast<double>(x0), static_cast<double>(y0)) * g.resolution;
  g.cells.assign(static_cast<std::size_t>(g.width) * g.height, kUnknown);
  for (const Cell& c : band) {
    std::int8_t& cell = g.cells[static_cast<std::size_t>(c.y - y0) * g.width + (c.x - x0)];
    if (c.occupied)
      cell = kOccupied;
    else if (cell == kUnknown)
      cell = kFree;
  }
  return g;
}

namespace {
// Image row 0 is the grid's top (largest y), as map_server reads it.
cv::Mat grey_image(const Grid2d& g) {
  cv::Mat img(g.height, g.width, CV_8UC1);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const std::int8_t c = g.at(x, y);
      img.at<std::uint8_t>(g.height - 1 - y, x) = c == kOccupied ? 0 : c == kFree ? 254 : 205;
    }
  return img;
}
}  // namespace

void write_map_server(const Grid2d& grid, const fs::path& out, const std::string& stem,
                      const MapServerThresholds& t) {
  const fs::path pgm = out / (stem + ".pgm");
  const fs::path yaml = out / (stem + ".yaml");
  const cv::Mat img = grid.cells.empty() ? cv::Mat(1, 1, CV_8UC1, cv::Scalar(205)) : grey_image(grid);
  io::write_image_file(pgm, img);
  std::string y = fmt::format("image: {}\nresolution: {:.6f}\norigin: [{:.6f}, {:.6f}, 0.0]\nnegate: 0\n",
                              pgm.filename().string(), grid.resolution, grid.origin.x(), grid.origin.y());
  y += fmt::format("occupied_thresh: {}\nfree_thresh: {}\n", t.occupied, t.free);
  const Eigen::Matrix3d& R = grid.floor.rotation;
  y += "# lrd-slam: the grid lies on the floor; floor frame = rotation x (SLAM map frame) - "
       "[0, 0, floor_height]\n";
  y += fmt::format(
      "lrd_floor_frame:\n  rotation: [{:.9f}, {:.9f}, {:.9f}, {:.9f}, {:.9f}, {:.9f}, {:.9f}, {:.9f}, "
      "{:.9f}]\n",
      R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2));
  y += fmt::format("  floor_height: {:.6f}\n  min_height: {}\n  max_height: {}\n", grid.floor.height,
                   grid.min_height, grid.max_height);
  util::write_file_bytes(yaml, y);
}

Grid2d read_map_server(const fs::path& yaml) {
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(yaml.string());
  } catch (const YAML::BadFile&) {
    throw file_error(yaml, "cannot read");
  } catch (const YAML::Exception& e) {
    throw file_error(yaml, std::string("not valid YAML: ") + e.what());
  }
  Grid2d g;
  fs::path image;
  double occupied = 0.65, free = 0.196;
  bool negate = false;
  try {
    for (const char* key : {"image", "resolution", "origin", "occupied_thresh", "free_thresh"})
      if (!doc[key]) throw file_error(yaml, std::string("no '") + key + "' key");
    image = doc["image"].as<std::string>();
    g.resolution = doc["resolution"].as<double>();
    const auto origin = doc["origin"].as<std::vector<double>>();
    if (origin.size() != 3) throw file_error(yaml, "'origin' must be [x, y, yaw]");
    g.origin = Eigen::Vector2d(origin[0], origin[1]);
    occupied = doc["occupied_thresh"].as<double>();
    free = doc["free_thresh"].as<double>();
    if (doc["negate"]) negate = doc["negate"].as<int>() != 0;
    if (const YAML::Node f = doc["lrd_floor_frame"]) {
      const auto r = f["rotation"].as<std::vector<double>>();
      if (r.size() != 9) throw file_error(yaml, "'lrd_floor_frame.rotation' must have 9 numbers");
      for (int i = 0; i < 9; ++i) g.floor.rotation(i / 3, i % 3) = r[static_cast<std::size_t>(i)];
      g.floor.height = f["floor_height"].as<double>();
      g.min_height = f["min_height"].as<double>();
      g.max_height = f["max_height"].as<double>();
    }
  } catch (const YAML::Exception& e) {
    throw file_error(yaml, std::string("bad value: ") + e.what());
  }
  if (!(g.resolution > 0)) throw file_error(yaml, "'resolution' must be > 0");
  if (image.is_relative()) image = yaml.parent_path() / image;
  const cv::Mat img = cv::imread(image.string(), cv::IMREAD_GRAYSCALE);
  if (img.empty()) throw file_error(image, "cannot read the grid image");
  g.width = img.cols;
  g.height = img.rows;
  g.cells.assign(static_cast<std::size_t>(g.width) * g.height, kUnknown);
  for (int r = 0; r < img.rows; ++r)
    for (int x = 0; x < img.cols; ++x) {
      const double v = img.at<std::uint8_t>(r, x);
      const double p = negate ? v / 255.0 : (255.0 - v) / 255.0;
      std::int8_t& c = g.cells[static_cast<std::size_t>(img.rows - 1 - r) * g.width + x];
      c = p > occupied ? kOccupied : p < free ? kFree : kUnknown;
    }
  return g;
}

void write_grid_picture(const Grid2d& grid, const std::vector<Eigen::Vector3d>& trajectory,
                        const fs::path& file) {
  if (grid.cells.empty()) {
    const cv::Mat empty(100, 100, CV_8UC3, cv::Scalar(205, 205, 205));
    io::write_image_file(file, empty);
    return;
  }
  const int scale = std::max(1, 800 / std::max(grid.width, grid.height));
  cv::Mat grey;
  cv::resize(grey_image(grid), grey, {}, scale, scale, cv::INTER_NEAREST);
  cv::Mat img;
  cv::cvtColor(grey, img, cv::COLOR_GRAY2BGR);
  std::vector<cv::Point> path;
  for (const Eigen::Vector3d& p : trajectory) {
    const Eigen::Vector3d q = grid.floor.to_floor(p);
    const double px = (q.x() - grid.origin.x()) / grid.resolution * scale;
    const double py = (q.y() - grid.origin.y()) / grid.resolution * scale;
    path.emplace_back(static_cast<int>(std::lround(px)),
                      static_cast<int>(std::lround(grid.height * scale - py)));
  }
  if (!path.empty()) {
    cv::polylines(img, path, false, cv::Scalar(200, 80, 0), 2, cv::LINE_AA);
    cv::circle(img, path.front(), 6, cv::Scalar(0, 160, 0), cv::FILLED, cv::LINE_AA);
    cv::circle(img, path.back(), 6, cv::Scalar(0, 0, 220), cv::FILLED, cv::LINE_AA);
  }
  io::write_image_file(file, img);
}

}  // namespace lrd::occupancy
