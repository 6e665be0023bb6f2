#include "lrd/synth/furniture.h"

namespace lrd::synth::furniture {
namespace {

Eigen::Isometry3f at(const Eigen::Isometry3f& base, float x, float y, float z) {
  Eigen::Isometry3f t = base;
  t.translate(Eigen::Vector3f(x, y, z));
  return t;
}

SurfaceStyle style(const TextureLibrary& tex, const char* name, float m, std::uint8_t cls,
                   MaskLabel label = MaskLabel::kStatic, float albedo = 1.0f) {
  SurfaceStyle s;
  s.texture = tex.id(name);
  s.metres_per_repeat = m;
  s.voc_class = cls;
  s.label = label;
  s.albedo = albedo;
  return s;
}

}  // namespace

void add_chair(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose,
               MaskLabel label) {
  const SurfaceStyle fabric = style(tex, "plaid_blue", 0.4f, voc::kChair, label);
  const SurfaceStyle metal = style(tex, "metal", 0.3f, voc::kChair, label, 0.7f);
  soup.add_box(at(pose, 0, 0, 0.45f), {0.46f, 0.46f, 0.06f}, fabric);
  soup.add_box(at(pose, -0.21f, 0, 0.75f), {0.05f, 0.44f, 0.5f}, fabric);
  for (float sx : {-0.19f, 0.19f})
    for (float sy : {-0.19f, 0.19f}) soup.add_box(at(pose, sx, sy, 0.21f), {0.035f, 0.035f, 0.42f}, metal);
}

void add_desk(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose, float length,
              float depth) {
  const SurfaceStyle wood = style(tex, "wood_furniture", 0.8f, voc::kDiningTable);
  const SurfaceStyle metal = style(tex, "metal", 0.3f, voc::kDiningTable, MaskLabel::kStatic, 0.6f);
  soup.add_box(at(pose, 0, 0, 0.74f), {depth, length, 0.04f}, wood);
  for (float sx : {-0.5f * depth + 0.05f, 0.5f * depth - 0.05f})
    for (float sy : {-0.5f * length + 0.05f, 0.5f * length - 0.05f})
      soup.add_box(at(pose, sx, sy, 0.36f), {0.05f, 0.05f, 0.72f}, metal);
  // A modesty panel gives the lower half of the view structure and texture.
  soup.add_box(at(pose, 0.5f * depth - 0.1f, 0, 0.45f), {0.02f, length - 0.15f, 0.45f}, wood);
}

void add_monitor(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose) {
  const SurfaceStyle shell = style(tex, "metal", 0.2f, voc::kTvMonitor, MaskLabel::kStatic, 0.4f);
  soup.add_box(at(pose, 0, 0, 0.02f), {0.2f, 0.25f, 0.02f}, shell);
  soup.add_box(at(pose, 0.02f, 0, 0.12f), {0.03f, 0.05f, 0.2f}, shell);
  soup.add_box(at(pose, 0, 0, 0.38f), {0.04f, 0.6f, 0.36f}, shell);
  // Screen facing +x, slightly proud of the shell.
  SurfaceStyle screen = style(tex, "screen", 1.0f, voc::kTvMonitor);
  const Eigen::Matrix3f R = pose.linear();
  const Eigen::Vector3f o = pose * Eigen::Vector3f(0.021f, -0.28f, 0.22f);
  soup.add_plane(o, R * Eigen::Vector3f(0, 0.56f, 0), R * Eigen::Vector3f(0, 0, 0.32f), screen, 0.3f, true);
  // Keyboard in front of it.
  soup.add_box(at(pose, 0.3f, 0, 0.015f), {0.15f, 0.45f, 0.03f}, style(tex, "books", 0.3f, voc::kBackground));
}

void add_bookshelf(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose, float width,
                   float height) {
  const SurfaceStyle wood = style(tex, "wood_furniture", 0.6f, voc::kBackground);
  const SurfaceStyle books = style(tex, "books", 0.7f, voc::kBackground);
  const float depth = 0.35f;
  soup.add_box(at(pose, -0.5f * depth + 0.01f, 0, 0.5f * height), {0.02f, width, height}, wood);
  for (float sy : {-0.5f * width, 0.5f * width})
    soup.add_box(at(pose, 0, sy, 0.5f * height), {depth, 0.03f, height}, wood);
  const int shelves = 5;
  for (int i = 0; i <= shelves; ++i) {
    const float z = 0.02f + (height - 0.04f) * static_cast<float>(i) / shelves;
    soup.add_box(at(pose, 0, 0, z), {depth, width, 0.03f}, wood);
    if (i < shelves) {
      // Book spines facing +x, filling most of the compartment.
      const float h = (height - 0.04f) / shelves - 0.06f;
      const Eigen::Matrix3f R = pose.linear();
      const Eigen::Vector3f o = pose * Eigen::Vector3f(0.05f, -0.5f * width + 0.04f, z + 0.02f);
      soup.add_plane(o, R * Eigen::Vector3f(0, width - 0.08f, 0), R * Eigen::Vector3f(0, 0, h), books, 0.4f);
    }
  }
}

void add_cabinet(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose) {
  const SurfaceStyle wood = style(tex, "wood_furniture", 0.5f, voc::kBackground, MaskLabel::kStatic, 0.9f);
  const SurfaceStyle items = style(tex, "desk_items", 0.5f, voc::kBackground);
  soup.add_box(at(pose, 0, 0, 0.5f), {0.5f, 1.0f, 1.0f}, wood, &items);
  const SurfaceStyle metal = style(tex, "metal", 0.2f, voc::kBackground, MaskLabel::kStatic, 1.3f);
  for (float z : {0.3f, 0.7f}) soup.add_box(at(pose, 0.26f, 0, z), {0.02f, 0.3f, 0.03f}, metal);
  soup.add_box(at(pose, 0, 0.25f, 1.15f), {0.25f, 0.3f, 0.3f},
               style(tex, "cardboard", 0.3f, voc::kBackground));
}

void add_sofa(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose) {
  const SurfaceStyle fabric = style(tex, "carpet", 0.5f, voc::kSofa, MaskLabel::kStatic, 1.4f);
  const SurfaceStyle cushion = style(tex, "plaid_red", 0.5f, voc::kSofa);
  soup.add_box(at(pose, 0, 0, 0.22f), {0.85f, 1.9f, 0.44f}, fabric, &cushion);
  soup.add_box(at(pose, -0.33f, 0, 0.62f), {0.2f, 1.9f, 0.45f}, fabric);
  for (float sy : {-0.9f, 0.9f}) soup.add_box(at(pose, 0, sy, 0.55f), {0.85f, 0.15f, 0.25f}, cushion);
}

void add_plant(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose) {
  const SurfaceStyle pot = style(tex, "brick", 0.5f, voc::kPottedPlant, MaskLabel::kStatic, 0.8f);
  const SurfaceStyle leaves = style(tex, "mural_meadow", 0.5f, voc::kPottedPlant);
  soup.add_prism(pose, 0.15f, 0.15f, 0.2f, 0.2f, 0.35f, 10, pot);
  soup.add_prism(at(pose, 0, 0, 0.35f), 0.2f, 0.2f, 0.35f, 0.3f, 0.5f, 9, leaves);
  soup.add_prism(at(pose, 0, 0, 0.85f), 0.35f, 0.3f, 0.05f, 0.05f, 0.45f, 9, leaves);
}

void add_carton(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose,
                const Eigen::Vector3f& size, MaskLabel label) {
  const SurfaceStyle s = style(tex, "cardboard", std::max(size.x(), size.y()), voc::kBackground, label);
  soup.add_box(pose, size, s);
}

}  // namespace lrd::synth::furniture
