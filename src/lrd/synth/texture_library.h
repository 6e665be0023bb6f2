#pragma once
// The synthetic benchmark's textures: real photographs from Debian packages (opencv-doc's
// example images, mate-backgrounds, gnome-backgrounds) mixed with procedural materials (brick,
// plaster, carpet, fabric, denim, skin, hair, book spines). Real photos give ORB the kind of
// texture it meets in real rooms; the procedural ones fill the roles no photo fits.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "lrd/synth/texture.h"

namespace lrd::synth {

using TextureId = std::uint16_t;

class TextureLibrary {
 public:
  // Loads the photographs (missing ones are replaced by procedural noise and logged once) and
  // generates the procedural materials; `seed` varies the procedural ones.
  explicit TextureLibrary(std::uint64_t seed);

  [[nodiscard]] TextureId id(const std::string& name) const;
  [[nodiscard]] const Texture& get(TextureId id) const { return textures_[id]; }
  [[nodiscard]] std::size_t size() const { return textures_.size(); }
  // Names of the photographs that were found and used (for the sequence's metadata).
  [[nodiscard]] const std::vector<std::string>& photo_sources() const { return photo_sources_; }
  [[nodiscard]] const std::vector<std::string>& missing_photos() const { return missing_photos_; }

  // Where the photographs are looked for; overridable for tests via LRD_TEXTURE_ROOT.
  static std::vector<std::filesystem::path> photo_search_roots();

 private:
  TextureId add(const std::string& name, const cv::Mat& image);
  void add_photo(const std::string& name, const std::string& relative_path, int max_side, std::uint64_t seed);

  std::vector<Texture> textures_;
  std::map<std::string, TextureId> ids_;
  std::vector<std::string> photo_sources_;
  std::vector<std::string> missing_photos_;
};

}  // namespace lrd::synth
