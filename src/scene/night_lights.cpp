// glsl/common/night_lights.glsl compiled as C++ in float (core/glsl_cpp.h), and the lights'
// intensity from a night image.
#include "scene/night_lights.h"

#include <algorithm>

#include "core/glsl_cpp.h"

namespace nph::scene {

namespace f32 {
using namespace nph::glsl;
using Number = float;
#include "../glsl/common/night_lights.glsl"
}  // namespace f32

std::vector<float> cityLightsIntensity(const LinearRgbImage& night) {
  std::vector<float> out(std::size_t(night.width) * std::size_t(night.height));
  for (std::size_t i = 0; i < out.size(); ++i) {
    const float r = night.rgb[3 * i], g = night.rgb[3 * i + 1], b = night.rgb[3 * i + 2];
    const float x = std::clamp((r - 0.5f * b) / 0.1f, 0.0f, 1.0f);
    const float lit = x * x * (3.0f - 2.0f * x);  // smoothstep(0, 0.1, R − B/2)
    out[i] = std::clamp(lit * (0.2126f * r + 0.7152f * g + 0.0722f * b), 0.0f, 1.0f);
  }
  return out;
}

float cityLightsFade(float sin_sun_elevation) { return f32::cityLightsFade(sin_sun_elevation); }

glm::vec3 cityLightsRadiance(float intensity, float sin_sun_elevation, const glm::vec3& sun_irradiance, float k) {
  return f32::cityLightsRadiance(intensity, sin_sun_elevation, sun_irradiance, k);
}

}  // namespace nph::scene
