#include "lrd/synth/texture_library.h"

#include <spdlog/spdlog.h>

#include <cstdlib>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "lrd/synth/procedural_texture.h"
#include "lrd/util/error.h"

namespace lrd::synth {
namespace fs = std::filesystem;

std::vector<fs::path> TextureLibrary::photo_search_roots() {
  std::vector<fs::path> roots;
  if (const char* env = std::getenv("LRD_TEXTURE_ROOT")) roots.emplace_back(env);
  roots.emplace_back("/usr/share/doc/opencv-doc/examples/data");
  roots.emplace_back("/usr/share/backgrounds");
  return roots;
}

TextureLibrary::TextureLibrary(std::uint64_t seed) {
  namespace p = procedural;
  // Photographs (role name, path under one of the roots, longest side kept).
  add_photo("poster_starry", "starry_night.jpg", 512, seed);
  add_photo("poster_fruits", "fruits.jpg", 512, seed);
  add_photo("poster_baboon", "baboon.jpg", 512, seed);
  add_photo("poster_building", "building.jpg", 512, seed);
  add_photo("poster_graffiti", "graf1.png", 512, seed);
  add_photo("poster_butterfly", "butterfly.jpg", 512, seed);
  add_photo("poster_leuven", "leuvenA.jpg", 512, seed);
  add_photo("poster_home", "home.jpg", 512, seed);
  add_photo("poster_messi", "messi5.jpg", 512, seed);
  add_photo("mural_garden", "mate/nature/Garden.jpg", 1024, seed);
  add_photo("mural_raindrops", "mate/nature/RainDrops.jpg", 1024, seed);
  add_photo("mural_ladybird", "mate/nature/LadyBird.jpg", 1024, seed);
  add_photo("mural_meadow", "mate/nature/GreenMeadow.jpg", 1024, seed);
  add_photo("mural_storm", "mate/nature/Storm.jpg", 1024, seed);
  add_photo("mural_wings", "mate/nature/TwoWings.jpg", 1024, seed);
  add_photo("wood_floor", "gnome/wood-l.webp", 1024, seed);
  add_photo("wood_furniture", "mate/nature/Wood.jpg", 512, seed);
  add_photo("screen", "mate/abstract/Elephants.jpg", 512, seed);
  add_photo("clothes_print", "mate/nature/YellowFlower.jpg", 256, seed);
  add_photo("clothes_flowers", "mate/nature/FreshFlower.jpg", 256, seed);
  add_photo("desk_items", "smarties.png", 512, seed);
  add_photo("box_print", "box.png", 256, seed);

  add("brick", p::brick(512, seed + 101));
  add("plaster_warm", p::plaster(512, cv::Scalar(170, 200, 220), seed + 102));
  add("plaster_cool", p::plaster(512, cv::Scalar(210, 200, 185), seed + 103));
  add("carpet", p::carpet(256, cv::Scalar(60, 70, 140), seed + 104));
  add("ceiling", p::ceiling_tiles(256, seed + 105));
  add("books", p::book_spines(512, seed + 106));
  add("plaid_red", p::plaid(256, cv::Scalar(40, 40, 170), cv::Scalar(30, 110, 30), seed + 107));
  add("plaid_blue", p::plaid(256, cv::Scalar(150, 80, 40), cv::Scalar(200, 200, 200), seed + 108));
  add("stripes_shirt", p::stripes(256, cv::Scalar(200, 200, 200), cv::Scalar(120, 60, 20), seed + 109));
  add("stripes_green", p::stripes(256, cv::Scalar(60, 150, 60), cv::Scalar(30, 40, 40), seed + 110));
  add("denim", p::denim(256, cv::Scalar(130, 80, 40), seed + 111));
  add("trousers_dark", p::denim(256, cv::Scalar(55, 50, 45), seed + 112));
  add("skin_light", p::skin(128, cv::Scalar(150, 175, 225), seed + 113));
  add("skin_dark", p::skin(128, cv::Scalar(70, 95, 140), seed + 114));
  add("hair_dark", p::hair(128, cv::Scalar(25, 30, 40), seed + 115));
  add("hair_brown", p::hair(128, cv::Scalar(30, 60, 100), seed + 116));
  add("cardboard", p::cardboard(256, seed + 117));
  add("metal", p::carpet(128, cv::Scalar(150, 150, 150), seed + 118));
  add("shoe", p::carpet(64, cv::Scalar(30, 30, 30), seed + 119));
  // A printed party balloon (balloon preset); added last, so every other texture keeps its id.
  add("balloon", p::stripes(256, cv::Scalar(50, 40, 215), cv::Scalar(40, 205, 235), seed + 120));
}

TextureId TextureLibrary::add(const std::string& name, const cv::Mat& image) {
  const auto id = static_cast<TextureId>(textures_.size());
  textures_.emplace_back(image);
  ids_[name] = id;
  return id;
}

void TextureLibrary::add_photo(const std::string& name, const std::string& relative_path, int max_side,
                               std::uint64_t seed) {
  for (const auto& root : photo_search_roots()) {
    const fs::path path = root / relative_path;
    if (!fs::exists(path)) continue;
    cv::Mat img = cv::imread(path.string(), cv::IMREAD_COLOR);
    if (img.empty()) continue;
    const double s = static_cast<double>(max_side) / std::max(img.cols, img.rows);
    if (s < 1.0) cv::resize(img, img, cv::Size(), s, s, cv::INTER_AREA);
    add(name, img);
    photo_sources_.push_back(path.string());
    return;
  }
  // Without the photo the room still renders (with a procedural stand-in), but the sequence is
  // then not the benchmark's: scripts/install-deps.sh installs the packages that provide them.
  spdlog::warn(
      "synth: photo texture '{}' not found (install opencv-doc, mate-backgrounds, gnome-backgrounds)",
      relative_path);
  missing_photos_.push_back(relative_path);
  add(name, procedural::carpet(std::min(max_side, 256), cv::Scalar(128, 128, 128), seed + textures_.size()));
}

TextureId TextureLibrary::id(const std::string& name) const {
  const auto it = ids_.find(name);
  if (it == ids_.end()) throw Error("synth: unknown texture '" + name + "'");
  return it->second;
}

}  // namespace lrd::synth
