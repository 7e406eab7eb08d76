#pragma once
// CPU twin of glsl/common/cloud_light.glsl (issue 12): the very functions the eye pass runs,
// compiled as C++ in double precision (core/glsl_cpp.h). Documentation in the GLSL file.
#include <glm/glm.hpp>

#include "lighting/render_settings.h"

namespace nph::lighting {

/// Henyey–Greenstein phase function [1/sr].
double hgPhase(double cos_psi, double g);
/// Nes eq. 5.12 mix of the ice and water lobes [1/sr]; ice_weight = β_ice/β.
double mixedPhase(double cos_psi, double ice_weight, double g_ice, double g_water);
/// Σ_{n<N} bⁿ·I^{aⁿ}·p_v(ψ; cⁿg) [1/sr] for the geometric series of `s` (free weights ignored:
/// see octaveSunFactor in lighting/octave_series.h for those).
double octaveSeries(double sunlight, double cos_psi, double ice_weight, double g_ice, double g_water,
                    const OctaveSeries& s);
/// Two-stream diffuse transmittance 1/(1 + ¾(1 − g)τ).
double diffuseTransmittance(double tau, double g);
/// Kasten–Young relative air mass.
double airMass(double sin_elevation);
/// Uniform clear-sky radiance per unit solar irradiance (linear RGB at 680/550/440 nm).
glm::dvec3 clearSkyRadiance(double sin_elevation);

/// The sky light of a scene (issue 12): the radiance of the upper hemisphere (the clear sky at the
/// sun's elevation, × the style's per-channel `ambient`) and of the lower one (the ground: ρ̄/π of
/// its sun and sky irradiance, or the sky again with `sky_below`); the sun's irradiance is
/// colour · intensity.
struct SkyLight {
  glm::dvec3 above{0.0};
  glm::dvec3 below{0.0};
};
SkyLight skyLightFor(const StyleSettings& style, double sun_elevation_deg, const glm::dvec3& sun_colour,
                     double sun_intensity);

}  // namespace nph::lighting
