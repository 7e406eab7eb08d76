#include "scene/sun.h"

#include <cmath>

namespace nph::scene {

glm::dvec3 Sun::toSun() const {
  const double az = glm::radians(azimuth_deg);
  const double el = glm::radians(elevation_deg);
  return {std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el)};
}

}  // namespace nph::scene
