#pragma once
// Software z-buffer rasterizer for the synthetic benchmark: perspective-correct textured
// triangles, per-triangle mip level, Lambert shading from one point light, and the ground-truth
// channels a real sensor cannot give (semantic class, dynamic label, incidence angle).
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/synth/texture_library.h"
#include "lrd/synth/triangle_soup.h"

namespace lrd::synth {

struct Lighting {
  Eigen::Vector3f light_position{3.0f, 2.5f, 2.8f};  // world
  float ambient = 0.45f;
  float diffuse = 0.75f;
  float falloff_distance = 4.0f;  // light intensity halves at this distance
};

// What one render pass produces. Pixels no surface covers have depth 0.
struct RenderBuffers {
  cv::Mat color;      // CV_8UC3 BGR
  cv::Mat depth;      // CV_32F, metres along the optical axis; +inf while rendering, 0 = empty after finish()
  cv::Mat voc_class;  // CV_8U, Pascal VOC class of the visible surface
  cv::Mat label;      // CV_8U, MaskLabel of the visible surface
  cv::Mat incidence;  // CV_32F, |cos| of the angle between viewing ray and surface normal

  [[nodiscard]] RenderBuffers clone() const;
};

class Rasterizer {
 public:
  Rasterizer(const camera::PinholeCamera& camera, const TextureLibrary& textures, Lighting lighting = {});

  // Fresh buffers: background colour, infinite depth.
  [[nodiscard]] RenderBuffers make_buffers() const;
  // Draws `tris` seen from the camera pose T_wc (camera-to-world).
  void draw(const std::vector<Triangle>& tris, const Eigen::Isometry3f& T_wc, RenderBuffers& buf) const;
  // Converts the z-buffer's "nothing" (+inf) into the sensor's 0.
  static void finish(RenderBuffers& buf);

 private:
  struct ClipVertex {
    Eigen::Vector3f p;  // camera frame
    Eigen::Vector2f uv;
  };
  void draw_triangle(const ClipVertex* v, const Triangle& tri, float shade, const Eigen::Vector3f& n_c,
                     RenderBuffers& buf) const;

  camera::PinholeCamera cam_;
  const TextureLibrary& textures_;
  Lighting lighting_;
};

}  // namespace lrd::synth
