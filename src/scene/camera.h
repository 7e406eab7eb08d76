#pragma once
// Pinhole camera shared by the GPU ray caster and the CPU references (same rays, same pixels).
// Pixel (px, py): px to the right, py DOWN (row 0 is the top row of the image, as written to
// files); the ray of a pixel passes through its centre (px + ½, py + ½) unless jittered.
#include <glm/glm.hpp>

namespace nph::scene {

struct Camera {
  glm::dvec3 position_m{0.0};
  glm::dvec3 target_m{0.0, 1.0, 0.0};
  glm::dvec3 up{0.0, 0.0, 1.0};
  double vertical_fov_deg = 45.0;
  int width = 1920;
  int height = 1080;
  double near_m = 10.0;
  double far_m = 1.0e8;

  /// Unit direction of the ray through image position (x, y) in pixels (x right, y down).
  glm::dvec3 rayDirection(double x, double y) const;
  glm::dmat4 viewFromWorld() const;
  glm::dmat4 clipFromView() const;  ///< OpenGL convention (NDC z in [-1, 1])
};

}  // namespace nph::scene
