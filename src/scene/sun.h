#pragma once
// The sun: a directional light. Direction is given as azimuth (clockwise from north, degrees) and
// elevation above the horizon (degrees), in the world frame of volume_frame.h (x east, y north,
// z up). `toSun()` is the unit vector pointing from the scene towards the sun.
#include <glm/glm.hpp>

namespace nph::scene {

struct Sun {
  double azimuth_deg = 135.0;        ///< 0 = north, 90 = east
  double elevation_deg = 45.0;       ///< 90 = zenith; ≤ 0 is below the horizon
  glm::dvec3 colour{1.0, 1.0, 1.0};  ///< linear RGB irradiance scale
  double intensity = 1.0;

  glm::dvec3 toSun() const;
};

}  // namespace nph::scene
