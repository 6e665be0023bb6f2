// `lrdslam map info FILE...`: what a map file (.lrdmap: --save-map, --autosave) holds, after every
// check a run loading it makes but the vocabulary and camera match (those need the run's).
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/commands.h"
#include "lrd/map/map.h"
#include "lrd/map/map_file.h"

namespace lrd::app {

namespace {

void info(const std::vector<std::string>& files) {
  for (const std::string& file : files) {
    map::Map map;
    // Throws one line naming the file: missing, truncated, corrupted, inconsistent.
    const map::MapFileHeader header = map::load_map_file(file, map);
    const camera::PinholeCamera& c = header.camera;
    std::printf(
        "%s: %zu keyframes, %zu map points, camera %dx%d fx %.3f fy %.3f, vocabulary %016llx (%llu words), "
        "%ju bytes\n",
        file.c_str(), map.keyframe_count(), map.map_point_count(), c.width, c.height, c.fx, c.fy,
        static_cast<unsigned long long>(header.vocabulary_fingerprint),
        static_cast<unsigned long long>(header.vocabulary_words),
        static_cast<std::uintmax_t>(std::filesystem::file_size(file)));
  }
}

}  // namespace

void register_map_command(CLI::App& app) {
  auto files = std::make_shared<std::vector<std::string>>();
  CLI::App* cmd = app.add_subcommand("map", "Map files (.lrdmap) written by run --save-map or --autosave");
  cmd->require_subcommand(1);
  CLI::App* in = cmd->add_subcommand(
      "info", "Check that each map file loads and print its keyframes, map points, camera and vocabulary");
  in->add_option("files", *files, "Map files (.lrdmap)")->required();
  in->callback([files] { info(*files); });
}

}  // namespace lrd::app
