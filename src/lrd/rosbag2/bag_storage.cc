#include "lrd/rosbag2/bag_storage.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "lrd/rosbag2/mcap_reader.h"
#include "lrd/rosbag2/sqlite_bag.h"
#include "lrd/util/error.h"

namespace lrd::rosbag2 {

namespace fs = std::filesystem;

namespace {

// A rosbag2 folder: its metadata.yaml names the storage and the file(s).
std::unique_ptr<BagStorage> open_folder(const fs::path& folder) {
  const fs::path metadata = folder / "metadata.yaml";
  YAML::Node info;
  std::string storage;
  std::vector<std::string> files;
  try {
    info = YAML::LoadFile(metadata.string())["rosbag2_bagfile_information"];
    if (!info) throw file_error(metadata, "no rosbag2_bagfile_information: not a rosbag2 metadata file");
    storage = info["storage_identifier"].as<std::string>("");
    for (const YAML::Node& f : info["relative_file_paths"]) files.push_back(f.as<std::string>());
  } catch (const YAML::Exception& e) {
    throw file_error(metadata, std::string("cannot read the rosbag2 metadata: ") + e.what());
  }
  if (files.size() != 1)
    throw file_error(metadata, fmt::format("the bag has {} files; one is read (rosbag2 split bags are not)",
                                           files.size()));
  const fs::path file = folder / files.front();
  if (storage == "mcap") return std::make_unique<McapReader>(file);
  if (storage == "sqlite3") return std::make_unique<Sqlite3Reader>(file);
  throw file_error(metadata, "storage_identifier '" + storage + "' is not one this reads (mcap, sqlite3)");
}

}  // namespace

std::unique_ptr<BagStorage> open_storage(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw file_error(path, "bag not found");
  if (fs::is_directory(path, ec)) {
    if (!fs::exists(path / "metadata.yaml", ec))
      throw file_error(path, "a folder without metadata.yaml is not a rosbag2 bag");
    return open_folder(path);
  }
  if (path.extension() == ".mcap") return std::make_unique<McapReader>(path);
  if (path.extension() == ".db3") return std::make_unique<Sqlite3Reader>(path);
  throw file_error(path, "not a ROS 2 bag (a .mcap or .db3 file, or a rosbag2 folder with metadata.yaml)");
}

}  // namespace lrd::rosbag2
