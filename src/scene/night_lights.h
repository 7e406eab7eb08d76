#pragma once
// City lights on the night side (issue 14 item 3): the lights' raster and the radiance they emit.
// The shading is glsl/common/night_lights.glsl (documented there); this module prepares the
// lights' intensity for the GPU (one float per imagery pixel, the A channel of the basemaps the
// eye pass samples) and compiles the shader's functions as C++ for the tests (core/glsl_cpp.h).
#include <vector>

#include <glm/glm.hpp>

#include "scene/basemap.h"

namespace nph::scene {

/// NASA's "Earth at night" (DMSP city lights, 2700×1350 whole-Earth JPEG, no georeference: the 2:1
/// rule of basemap.h) from Debian's marble-qt-data, beside the Blue Marble default. The default
/// night-lights raster of a scene with a basemap (scene_file.h BasemapSpec::night_lights).
inline constexpr const char* kCityLightsPath = "/usr/share/marble/data/maps/earth/citylights/citylights.jpg";

/// The lights alone, one intensity in [0, 1] per pixel, from a linear-RGB night image:
///   I = Y · smoothstep(0, 0.1, R − B/2),
/// Y the Rec.709 luminance. citylights.jpg draws land and ice as a dark blue (linear ≈ (0.02, 0.02,
/// 0.10): R − B/2 < 0, dropped) and the lights as warm white (R − B/2 ≈ 0.5, kept at their
/// luminance); a grey or white raster of lights (R = G = B ≥ 0.2) passes as its luminance.
std::vector<float> cityLightsIntensity(const LinearRgbImage& night);

/// CPU twins of glsl/common/night_lights.glsl (the same file compiled as C++ in float).
float cityLightsFade(float sin_sun_elevation);
glm::vec3 cityLightsRadiance(float intensity, float sin_sun_elevation, const glm::vec3& sun_irradiance, float k);

}  // namespace nph::scene
