// glsl/common/cloud_light.glsl compiled as C++ in double precision (core/glsl_cpp.h).
#include "lighting/cloud_light.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/glsl_cpp.h"

namespace nph::lighting {

namespace f64 {
using namespace nph::glsl;
using Number = double;
using Vec3 = glm::dvec3;
#include "../glsl/common/cloud_light.glsl"
}  // namespace f64

double hgPhase(double cos_psi, double g) { return f64::hgPhase(cos_psi, g); }
double mixedPhase(double cos_psi, double ice_weight, double g_ice, double g_water) {
  return f64::mixedPhase(cos_psi, ice_weight, g_ice, g_water);
}
double octaveSeries(double sunlight, double cos_psi, double ice_weight, double g_ice, double g_water,
                    const OctaveSeries& s) {
  return f64::octaveSeries(sunlight, cos_psi, ice_weight, g_ice, g_water, s.octaves, s.extinction_scale, s.energy_scale,
                           s.anisotropy_scale);
}
double twoStreamDiffuse(double tau_above, double tau_below, double mu0, double flux_scale, double diffusion_scale,
                        double mu_out, double g) {
  return f64::twoStreamDiffuse(tau_above, tau_below, mu0, flux_scale, diffusion_scale, mu_out, g);
}
double twoStreamColumn(double tau_above, double tau_below, double mu0, double flux_scale, double k, double K, double b,
                       double mu_out, double g) {
  return f64::twoStreamColumn(tau_above, tau_below, mu0, flux_scale, k, K, b, mu_out, g);
}
glm::dvec2 twoStreamColumnMoments(double tau_above, double tau_below, double mu0, double flux_scale, double k, double K,
                                  double b, double g) {
  return glm::dvec2(f64::twoStreamColumnMoments(tau_above, tau_below, mu0, flux_scale, k, K, b, g));
}
double forwardLobe(double sunlight, double cos_psi, double g, double tau_above, double mu0) {
  return f64::forwardLobe(sunlight, cos_psi, g, tau_above, mu0);
}
glm::dvec3 twoStreamSunFrame(double mu_world, double exaggeration) {
  return f64::twoStreamSunFrame(mu_world, exaggeration);
}
double cloudSunFactor(const RenderSettings& s, double sunlight, double cos_psi, double ice_weight,
                      const glm::dvec2& tau, const glm::dvec3& sun_frame, double mu_out) {
  if (s.multiple_scattering == MultipleScattering::Octaves && !s.octaves.energy.empty())
    return octaveSunFactor(s.octaves, sunlight, cos_psi, ice_weight, s.g_ice, s.g_water);
  return f64::cloudSunFactor(int(s.multiple_scattering), sunlight, cos_psi, ice_weight, s.g_ice, s.g_water,
                             s.octaves.octaves, s.octaves.extinction_scale, s.octaves.energy_scale,
                             s.octaves.anisotropy_scale, tau.x, tau.y, sun_frame, mu_out);
}
double diffuseTransmittance(double tau, double g) { return f64::diffuseTransmittance(tau, g); }
glm::dvec3 skyDiffuse(double tau_above, double tau_below, double g, double diffusion_scale, const glm::dvec3& above,
                      const glm::dvec3& below) {
  return f64::skyDiffuse(tau_above, tau_below, g, diffusion_scale, above, below);
}
double airMass(double sin_elevation) { return f64::airMass(sin_elevation); }
glm::dvec3 clearSkyRadiance(double sin_elevation) { return f64::clearSkyRadiance(sin_elevation); }

SkyLight skyLightFor(const StyleSettings& style, double sun_elevation_deg, const glm::dvec3& sun_colour,
                     double sun_intensity) {
  const double sinH = std::sin(glm::radians(sun_elevation_deg));
  const glm::dvec3 sun_irradiance = sun_colour * sun_intensity;
  SkyLight s;
  // The clear sky scales with the sun's intensity, not its colour (the colour tints the direct beam).
  s.above = clearSkyRadiance(sinH) * style.ambient * sun_intensity;
  s.below = style.sky_below ? s.above
                            : style.ground_albedo / std::numbers::pi *
                                  (sun_irradiance * std::max(sinH, 0.0) + std::numbers::pi * s.above);
  return s;
}

double octaveSunFactor(const OctaveSeries& s, double sunlight, double cos_psi, double ice_weight, double g_ice,
                       double g_water) {
  if (s.energy.empty()) return octaveSeries(sunlight, cos_psi, ice_weight, g_ice, g_water, s);
  double sum = 0.0, depth = 1.0, aniso = 1.0;
  for (std::size_t n = 0; n < s.energy.size(); ++n) {
    const double light = n == 0 ? sunlight : (sunlight > 0.0 ? std::pow(sunlight, depth) : 0.0);
    sum += s.energy[n] * light * mixedPhase(cos_psi, ice_weight, aniso * g_ice, aniso * g_water);
    depth *= s.extinction_scale;
    aniso *= s.anisotropy_scale;
  }
  return sum;
}

}  // namespace nph::lighting
