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
/// Independent-column δ-Eddington diffuse radiance of sunlight per unit irradiance [1/sr] at a sample
/// τ_above below the top of a conservative slab of τ_above + τ_below, sun at μ₀, scattered towards
/// a direction of vertical cosine μ_out (glsl/common/cloud_light.glsl twoStreamDiffuse).
double twoStreamDiffuse(double tau_above, double tau_below, double mu0, double flux_scale, double diffusion_scale,
                        double mu_out, double g);
/// The same column with its resistance k, drift constant K and Marshak constant b free
/// (glsl/common/cloud_light.glsl twoStreamColumn; K = 1, b = ⅔ is twoStreamDiffuse).
double twoStreamColumn(double tau_above, double tau_below, double mu0, double flux_scale, double k, double K, double b,
                       double mu_out, double g);
/// Its moments (I₀, I₁) per unit irradiance.
glm::dvec2 twoStreamColumnMoments(double tau_above, double tau_below, double mu0, double flux_scale, double k, double K,
                                  double b, double g);
/// The once-scattered light's forward lobe restored [1/sr] (glsl/common/cloud_light.glsl
/// forwardLobe): the cone's light through p(ψ; g²), the first diffuse order's lobe through
/// p(ψ; g·g'); integrates to 0 over the sphere.
double forwardLobe(double sunlight, double cos_psi, double g, double tau_above, double mu0);
/// (μ₀ in the data, beam scale, vertical diffusion scale) of a sun of world vertical cosine μ_w under
/// height exaggeration e (glsl/common/cloud_light.glsl twoStreamSunFrame).
glm::dvec3 twoStreamSunFrame(double mu_world, double exaggeration);
/// The sunlight a sample scatters towards the eye per unit irradiance [1/sr] by `s.multiple_scattering`
/// (glsl/common/cloud_light.glsl cloudSunFactor; the octaves' free weights, when set, by
/// octaveSunFactor): `sunlight` the DLM's I, `tau` the column depths (τ_above, τ_below), `sun_frame`
/// twoStreamSunFrame's, `mu_out` the vertical cosine towards the eye in the data.
double cloudSunFactor(const RenderSettings& s, double sunlight, double cos_psi, double ice_weight,
                      const glm::dvec2& tau, const glm::dvec3& sun_frame, double mu_out);
/// Two-stream diffuse transmittance 1/(1 + ¾(1 − g)τ).
double diffuseTransmittance(double tau, double g);
/// Mean radiance I₀ at a sample τ_above below the top of a conservative Eddington slab of
/// τ_above + τ_below lit by diffuse radiance `above` and `below` (glsl/common/cloud_light.glsl
/// skyDiffuse): the sky light a cloud sample scatters; `above` everywhere when above = below.
glm::dvec3 skyDiffuse(double tau_above, double tau_below, double g, double diffusion_scale, const glm::dvec3& above,
                      const glm::dvec3& below);
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
