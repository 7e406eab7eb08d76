#include "scene/camera.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace nph::scene {

glm::dvec3 Camera::rayDirection(double x, double y) const {
  const glm::dvec3 forward = glm::normalize(target_m - position_m);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, up));
  const glm::dvec3 trueUp = glm::cross(right, forward);
  const double tanHalf = std::tan(glm::radians(vertical_fov_deg) * 0.5);
  const double aspect = double(width) / double(height);
  const double ndcX = (2.0 * x / double(width) - 1.0) * tanHalf * aspect;
  const double ndcY = (1.0 - 2.0 * y / double(height)) * tanHalf;
  return glm::normalize(forward + ndcX * right + ndcY * trueUp);
}

glm::dmat4 Camera::viewFromWorld() const { return glm::lookAt(position_m, target_m, up); }

glm::dmat4 Camera::clipFromView() const {
  return glm::perspective(glm::radians(vertical_fov_deg), double(width) / double(height), near_m, far_m);
}

}  // namespace nph::scene
