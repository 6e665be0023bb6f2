#include "lrd/synth/room_scene.h"

#include <cmath>

#include "lrd/synth/furniture.h"

namespace lrd::synth {
namespace {

SurfaceStyle wall_style(const TextureLibrary& tex, const char* name, float m, float albedo = 1.0f) {
  SurfaceStyle s;
  s.texture = tex.id(name);
  s.metres_per_repeat = m;
  s.albedo = albedo;
  return s;
}

// A poster hung 1 cm in front of a wall: `origin` lower-left corner, `right` and `up` its edges.
void add_poster(TriangleSoup& soup, const TextureLibrary& tex, const char* name,
                const Eigen::Vector3f& origin, const Eigen::Vector3f& right, const Eigen::Vector3f& up) {
  soup.add_plane(origin, right, up, wall_style(tex, name, 1.0f), 0.5f, true);
}

}  // namespace

Eigen::Isometry3f floor_pose(float x, float y, float yaw, float z) {
  Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
  t.translate(Eigen::Vector3f(x, y, z));
  t.rotate(Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitZ()));
  return t;
}

std::vector<Eigen::Isometry3f> RoomLayout::seat_poses() {
  const Eigen::Vector3f d = desk_center();
  const float pi = static_cast<float>(M_PI);
  return {floor_pose(d.x() + 0.55f, d.y() - 0.33f, pi), floor_pose(d.x() + 0.55f, d.y() + 0.33f, pi)};
}

TriangleSoup build_room(const TextureLibrary& tex) {
  using V = Eigen::Vector3f;
  const float L = RoomLayout::kLength, W = RoomLayout::kWidth, H = RoomLayout::kHeight;
  TriangleSoup soup;
  // Floor, rug, ceiling.
  soup.add_plane(V(0, 0, 0), V(L, 0, 0), V(0, W, 0), wall_style(tex, "wood_floor", 1.5f, 0.9f), 0.5f);
  soup.add_plane(V(2.6f, 1.2f, 0.004f), V(1.6f, 0, 0), V(0, 2.4f, 0), wall_style(tex, "carpet", 0.8f), 0.4f);
  soup.add_plane(V(0, W, H), V(L, 0, 0), V(0, -W, 0), wall_style(tex, "ceiling", 0.6f), 0.6f);
  // Walls, normals pointing into the room.
  soup.add_plane(V(L, W, 0), V(0, -W, 0), V(0, 0, H), wall_style(tex, "plaster_warm", 1.2f),
                 0.5f);  // front, x = L
  soup.add_plane(V(0, 0, 0), V(0, W, 0), V(0, 0, H), wall_style(tex, "mural_garden", 1.1f),
                 0.5f);  // back, x = 0
  soup.add_plane(V(L, 0, 0), V(-L, 0, 0), V(0, 0, H), wall_style(tex, "plaster_cool", 1.2f),
                 0.5f);                                                                      // right, y = 0
  soup.add_plane(V(0, W, 0), V(L, 0, 0), V(0, 0, H), wall_style(tex, "brick", 1.0f), 0.5f);  // left, y = W

  // Posters: front wall (seen by the walking/sitting presets), then the others (seen by the loops).
  const float e = 0.01f;
  add_poster(soup, tex, "poster_starry", V(L - e, 4.1f, 1.2f), V(0, -1.0f, 0), V(0, 0, 0.8f));
  add_poster(soup, tex, "mural_raindrops", V(L - e, 3.1f, 1.35f), V(0, -1.3f, 0), V(0, 0, 0.95f));
  add_poster(soup, tex, "poster_building", V(L - e, 1.5f, 1.2f), V(0, -0.7f, 0), V(0, 0, 0.95f));
  add_poster(soup, tex, "poster_fruits", V(L - e, 0.65f, 1.0f), V(0, -0.5f, 0), V(0, 0, 0.5f));
  add_poster(soup, tex, "poster_graffiti", V(L - e, 3.9f, 0.1f), V(0, -0.9f, 0), V(0, 0, 0.7f));
  add_poster(soup, tex, "poster_baboon", V(e, 0.6f, 1.1f), V(0, 0.7f, 0), V(0, 0, 0.7f));
  add_poster(soup, tex, "poster_leuven", V(e, 3.4f, 1.0f), V(0, 1.1f, 0), V(0, 0, 0.85f));
  add_poster(soup, tex, "mural_storm", V(4.9f, e, 1.0f), V(-1.4f, 0, 0), V(0, 0, 1.0f));
  add_poster(soup, tex, "poster_butterfly", V(2.6f, e, 1.3f), V(-0.7f, 0, 0), V(0, 0, 0.5f));
  add_poster(soup, tex, "poster_home", V(1.4f, e, 1.1f), V(-0.9f, 0, 0), V(0, 0, 0.7f));
  add_poster(soup, tex, "mural_ladybird", V(3.3f, W - e, 1.2f), V(1.2f, 0, 0), V(0, 0, 0.9f));
  add_poster(soup, tex, "poster_messi", V(4.9f, W - e, 1.4f), V(0.8f, 0, 0), V(0, 0, 0.5f));
  add_poster(soup, tex, "mural_wings", V(0.3f, W - e, 2.05f), V(0.9f, 0, 0), V(0, 0, 0.6f));

  const float pi = static_cast<float>(M_PI);
  const Eigen::Vector3f d = RoomLayout::desk_center();
  furniture::add_desk(soup, tex, floor_pose(d.x(), d.y(), 0), RoomLayout::kDeskLength,
                      RoomLayout::kDeskDepth);
  // Monitors at the desk's ends, so the people seated between them stay in view.
  furniture::add_monitor(soup, tex, floor_pose(d.x() + 0.1f, d.y() - 0.72f, pi + 0.25f, 0.76f));
  furniture::add_monitor(soup, tex, floor_pose(d.x() + 0.1f, d.y() + 0.72f, pi - 0.3f, 0.76f));
  for (const auto& seat : RoomLayout::seat_poses()) furniture::add_chair(soup, tex, seat);
  furniture::add_bookshelf(soup, tex, floor_pose(1.8f, W - 0.2f, -0.5f * pi), 1.6f, 1.9f);
  furniture::add_cabinet(soup, tex, floor_pose(4.2f, 0.3f, 0.5f * pi));
  furniture::add_sofa(soup, tex, floor_pose(0.5f, 2.2f, 0.0f));
  furniture::add_plant(soup, tex, floor_pose(5.55f, 0.45f, 0.0f));
  furniture::add_plant(soup, tex, floor_pose(0.45f, 4.55f, 0.7f));
  furniture::add_chair(soup, tex, floor_pose(1.3f, 0.6f, 0.5f * pi));
  furniture::add_carton(soup, tex, floor_pose(5.6f, 4.55f, 0.2f, 0.2f), {0.5f, 0.4f, 0.4f},
                        MaskLabel::kStatic);
  return soup;
}

}  // namespace lrd::synth
