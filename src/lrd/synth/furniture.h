#pragma once
// Furniture pieces of the synthetic room, built from boxes and prisms. Each is placed by a pose
// whose origin is on the floor (z up) and whose +x is the piece's front.
#include <Eigen/Geometry>

#include "lrd/synth/texture_library.h"
#include "lrd/synth/triangle_soup.h"

namespace lrd::synth::furniture {

// `label` marks a piece that is being moved (walking_pushed); static pieces keep kStatic.
void add_chair(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose,
               MaskLabel label = MaskLabel::kStatic);
void add_desk(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose, float length,
              float depth);
void add_monitor(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose);
void add_bookshelf(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose, float width,
                   float height);
void add_cabinet(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose);
void add_sofa(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose);
void add_plant(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose);
// A cardboard box of the given size, centred at the pose's origin.
void add_carton(TriangleSoup& soup, const TextureLibrary& tex, const Eigen::Isometry3f& pose,
                const Eigen::Vector3f& size, MaskLabel label);

}  // namespace lrd::synth::furniture
