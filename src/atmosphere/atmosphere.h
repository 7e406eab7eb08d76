#pragma once
// The Earth's clear atmosphere around the clouds (issue 14 item 1): Rayleigh, Mie and ozone, as in
// Bruneton 2017 ("Precomputed atmospheric scattering: a new implementation", the constants of his
// demo) and Hillaire 2020 ("A Scalable and Production Ready Sky and Atmosphere Rendering
// Technique", EGSR; his Table 1 / reference code). This header is the model and its CPU
// double-precision evaluation, the oracle of the GPU look-up tables (render/atmosphere/, the
// shaders in glsl/atmosphere/); GL-free.
//
// Radiometric convention (issue 12): the sun is a directional light of irradiance E at the top of
// the atmosphere; every function here is per unit E (E = 1), so a sky radiance is in 1/sr and an
// irradiance is dimensionless. Phase functions integrate to 1 over the sphere.
//
// Geometry: the planet is a sphere of radius bottom_radius_m centred at the origin; a point is
// given by its radius r (distance to the centre) and a direction by its cosine μ with the local
// zenith (Bruneton's (r, μ)). Where a function takes vectors they are in a frame centred on the
// planet; `localFrame` helpers put the observer at (0, 0, r).
//
// The model, Hillaire 2020 §4:
//   σ_s(h) = ρ_R(h)·β_R + ρ_M(h)·β_M^s,  σ_t(h) = ρ_R(h)·β_R + ρ_M(h)·(β_M^s + β_M^a) + ρ_O(h)·β_O
//   with ρ_R = e^{−h/H_R}, ρ_M = e^{−h/H_M}, ρ_O the tent max(0, 1 − |h − h_O|/w_O);
//   T(x, y) = exp(−∫_x^y σ_t)                                                       (eq. 2)
//   L(c, v) = ∫_0^{t_max} T(c, x) · S(x) dt,  x = c + t·v                           (eq. 1)
//   S(x) = σ_s^R(x)·(V·T_sun(x)·p_R(θ) + Ψ_ms(x)) + σ_s^M(x)·(V·T_sun(x)·p_M(θ) + Ψ_ms(x))  (eq. 3, 11)
//   with V the planet's shadow (soft over the sun's disc, Bruneton 2017 GetTransmittanceToSun) and
//   Ψ_ms Hillaire's multiple-scattering approximation (eqs. 5–10), see multipleScattering().
#include <glm/glm.hpp>

namespace nph::atmosphere {

/// The atmosphere's constants. Defaults: Hillaire 2020's Earth (his reference code's
/// `GetAtmosphereParameters`, the same numbers as Bruneton 2017's demo), with the planet radius of
/// the renderer's globe (volume::kEarthRadius_m = 6370 km; Bruneton and Hillaire use 6360 km).
struct Parameters {
  double bottom_radius_m = 6370000.0;  ///< planet radius (ground at sea level)
  double top_radius_m = 6470000.0;     ///< top of the atmosphere: 100 km above the ground
  glm::dvec3 rayleigh_scattering_per_m{5.802e-6, 13.558e-6, 33.1e-6};  ///< β_R at the ground
  double rayleigh_scale_height_m = 8000.0;                             ///< H_R
  glm::dvec3 mie_scattering_per_m{3.996e-6};                           ///< β_M^s at the ground
  glm::dvec3 mie_absorption_per_m{0.444e-6};                           ///< β_M^a (extinction 4.40e-6 /m)
  double mie_scale_height_m = 1200.0;                                  ///< H_M
  double mie_g = 0.8;                                                  ///< Cornette–Shanks asymmetry
  glm::dvec3 ozone_absorption_per_m{0.650e-6, 1.881e-6, 0.085e-6};     ///< β_O at the tent's peak
  double ozone_center_m = 25000.0;                                     ///< h_O: the ozone tent peaks here …
  double ozone_half_width_m = 15000.0;                                 ///< … and falls to 0 this far above and below
  glm::dvec3 ground_albedo{0.3};             ///< Lambertian ground of the multiple-scattering term
  double sun_angular_radius_rad = 0.004675;  ///< softens the planet's shadow edge (Bruneton)
  bool multiple_scattering = true;           ///< Ψ_ms on (Hillaire) or single scattering only

  /// The Earth (the defaults).
  static Parameters earth() { return {}; }
};

/// Scattering and extinction coefficients at one altitude [1/m].
struct Medium {
  glm::dvec3 rayleigh_scattering_per_m{0.0};
  glm::dvec3 mie_scattering_per_m{0.0};
  glm::dvec3 extinction_per_m{0.0};
};
Medium mediumAt(const Parameters& p, double altitude_m);
/// The ozone's absorption at an altitude (the tent; part of mediumAt's extinction) [1/m].
glm::dvec3 ozoneAbsorption(const Parameters& p, double altitude_m);

/// The factor on the ozone's absorption along a plane-parallel ray of zenith cosine μ (issue 14,
/// the flat view's horizon): such a ray crosses the ozone layer (2·w thick) over 2w/|μ|, without
/// bound as μ → 0, where a straight ray through the planet's layer crosses at most its chord
/// tangent to the layer's bottom, 2·√(2R·2w) = 1237 km; the factor keeps the plane-parallel path
/// within that: min(1, |μ|·chord/2w), 1 for rays steeper than 1.4°. Without it the flat view's
/// grazing rays took thousands of kilometres of Chappuis absorption (green): a magenta horizon.
double planeParallelOzoneCap(const Parameters& p, double mu);

/// Rayleigh phase function 3/(16π)·(1 + cos²θ); ∫ p dΩ = 1.
double rayleighPhase(double cos_theta);
/// Cornette–Shanks phase function (Bruneton 2017 MiePhaseFunction; Hillaire's Mie phase):
/// 3/(8π)·(1 − g²)(1 + cos²θ) / ((2 + g²)(1 + g² − 2g·cosθ)^{3/2}); ∫ p dΩ = 1.
double miePhase(double cos_theta, double g);

/// Distance from radius r along zenith cosine μ to the top of the atmosphere (Bruneton 2017
/// DistanceToTopAtmosphereBoundary) and to the ground (DistanceToBottomAtmosphereBoundary; only
/// meaningful when rayHitsGround).
double distanceToTop(const Parameters& p, double r_m, double mu);
double distanceToGround(const Parameters& p, double r_m, double mu);
bool rayHitsGround(const Parameters& p, double r_m, double mu);

/// How finely the CPU evaluation integrates (every integral is a sum of these many pieces).
struct Quadrature {
  int view_steps = 128;                       ///< along a view ray or segment
  int transmittance_steps = 128;              ///< from a point to the top of the atmosphere
  int ms_directions_mu = 8;                   ///< Ψ_ms: sphere of directions, bands of equal cos θ …
  int ms_directions_phi = 8;                  ///< … times equal azimuth cells
  int ms_steps = 32;                          ///< Ψ_ms: along each direction
  int ms_transmittance_steps = 64;            ///< Ψ_ms: sunlight to each of its samples
  int irradiance_mu = 8, irradiance_phi = 8;  ///< skyIrradiance's hemisphere (azimuth: half, mirrored)
};

/// Transmittance from radius r along zenith cosine μ to the top of the atmosphere (the ground is
/// ignored), by the midpoint rule in `steps` pieces (Hillaire eq. 2; Bruneton's transmittance
/// texture holds the same function).
glm::dvec3 transmittanceToTop(const Parameters& p, double r_m, double mu, int steps);
/// The sunlight that reaches radius r with the sun at zenith cosine μ_s: transmittanceToTop times
/// the visible fraction of the sun's disc above the planet's horizon (Bruneton 2017
/// GetTransmittanceToSun: a linear ramp over the disc).
glm::dvec3 sunTransmittance(const Parameters& p, double r_m, double mu_s, int steps);
/// The fraction of the sun's disc above the horizon seen from radius r (0 … 1).
double sunVisibility(const Parameters& p, double r_m, double mu_s);

/// Hillaire 2020's multiple-scattering term Ψ_ms at radius r, sun zenith cosine μ_s (eqs. 5–10):
/// from x, rays in every direction ω gather once-scattered sunlight (isotropic phase p_u = 1/4π)
/// plus the lit ground's Lambertian reflection:
///   L_2nd = ∫_Ω L'(x, −ω)·p_u dω,   f_ms = ∫_Ω L_f(x, −ω)·p_u dω,  L_f = ∫ T·σ_s dt,
///   F_ms = 1 / (1 − f_ms),  Ψ_ms = L_2nd·F_ms      (infinite orders of isotropic re-scattering).
/// Zero when Parameters::multiple_scattering is off.
glm::dvec3 multipleScattering(const Parameters& p, double r_m, double mu_s, const Quadrature& q);

/// What a segment adds to and takes from the light behind it: transmittance T(c, c + t·v) and the
/// in-scattered radiance ∫ T·S dt (per unit solar irradiance).
struct Segment {
  glm::dvec3 transmittance{1.0};
  glm::dvec3 inscattered{0.0};
};

/// The segment from `origin_m` (planet-centred) along unit `dir` for `length_m`, with the sun
/// towards unit `to_sun`. Each piece is integrated with σ_t and S held at its midpoint:
/// ∫ e^{−σ_t t} S dt = S·(1 − e^{−σ_t Δ})/σ_t (Hillaire 2020 §5.1, after Hillaire 2015).
/// `plane_parallel`: the altitude is origin's plus t·dir.z and the sun's zenith cosine is
/// to_sun.z everywhere (the flat view's world, where the ground is the plane z = 0), the ozone's
/// absorption times planeParallelOzoneCap(dir.z). `flat_sun`: the sun's zenith cosine is to_sun.z
/// everywhere on a round ray too (the flat view's sun over a round chord, aerialPerspectiveOfFlatPoint).
Segment integrateSegment(const Parameters& p, const glm::dvec3& origin_m, const glm::dvec3& dir, double length_m,
                         const glm::dvec3& to_sun, const Quadrature& q, bool plane_parallel = false,
                         bool flat_sun = false);

/// A point of the flat view's world carried onto the round planet (issue 14, thirteenth session:
/// the clouds' aerial perspective). The flat world is a map: a point `length_m` along unit `dir`
/// from an eye `eye_altitude_m` up lies D = length·|dir_xy| away over the ground at altitude
/// h = h0 + length·dir.z. On the planet the same point (ground distance D, altitude h) is seen along
/// the straight chord from the eye at observerAt(h0): that chord sags below the straight line of
/// the flat world by up to D²/(8R) (1.8 km at 300 km: denser air).
struct RoundChord {
  glm::dvec3 origin_m{0.0};  ///< the eye, planet-centred: observerAt(eye_altitude_m)
  glm::dvec3 dir{0.0};       ///< unit, in the eye's local frame (x, y horizontal as the flat view's)
  double length_m = 0.0;
};
RoundChord flatPointOnRoundPlanet(const Parameters& p, double eye_altitude_m, const glm::dvec3& dir, double length_m);

/// The aerial perspective of a point of the flat view in the air (a cloud): integrateSegment along
/// its round chord, the part inside the top sphere (an eye above the atmosphere looks in through
/// it), with the flat view's sun: zenith cosine to_sun.z all along, as the clouds are lit. Where the chord passes below
/// the ground (the point beyond the eye's horizon and the eye beyond its), the air there is the ground's. Twin of
/// glsl/atmosphere/sky.glsl aerialPerspectiveOfFlatPoint.
Segment aerialPerspectiveOfFlatPoint(const Parameters& p, double eye_altitude_m, const glm::dvec3& dir, double length_m,
                                     const glm::dvec3& to_sun, const Quadrature& q);

/// Sky radiance seen from `origin_m` (planet-centred, inside or outside the atmosphere) along
/// unit `dir`: the segment through the atmosphere up to the ground or space (the ground's own
/// radiance is not included). Per unit solar irradiance [1/sr].
glm::dvec3 skyRadiance(const Parameters& p, const glm::dvec3& origin_m, const glm::dvec3& dir, const glm::dvec3& to_sun,
                       const Quadrature& q);

/// Irradiance of a horizontal surface at `altitude_m` from the sky alone (the direct sun left
/// out) with the sun at elevation `sun_elevation_rad`: E_sky = ∫_{upper hemisphere} L·cos θ dΩ,
/// per unit solar irradiance — the sky-light term of the ground and of the clouds' shadowed sides.
glm::dvec3 skyIrradiance(const Parameters& p, double altitude_m, double sun_elevation_rad, const Quadrature& q);

/// What a light meter reads (issue 14, the exposure that follows the sun): the illuminance of a
/// horizontal surface at `altitude_m` per unit solar irradiance, as luminance (Rec. 709 weights of
/// the model's 680/550/440 nm channels): the direct sun μ_s·T_sun plus the sky's E_sky, the sky
/// integrated coarsely (6 × 6 directions, 48 steps) and once scattered only — a meter, not the
/// image's light: Hillaire's Ψ_ms adds ≈ 10 % to E_sky at noon and more at twilight, and a meter's
/// ±0.1 EV does not show. 0.1 ms.
double horizontalIlluminance(const Parameters& p, double altitude_m, double sun_elevation_rad);
/// The same meter per channel: the irradiance of a horizontal surface at `altitude_m`, direct sun
/// μ_s·T_sun plus the once-scattered sky (per unit solar irradiance). The ground under the clouds
/// is lit by this: its Lambertian bounce ρ̄/π·E·horizontalIrradiance is the light the clouds' bases
/// get from below (render/raycast/cloud_renderer.cpp; issue 14, seventeenth session).
glm::dvec3 horizontalIrradiance(const Parameters& p, double altitude_m, double sun_elevation_rad);

/// The observer at altitude h above the ground at the north pole of the planet-centred frame:
/// (0, 0, R + h); local directions (x, y horizontal, z up) are then planet-frame directions.
inline glm::dvec3 observerAt(const Parameters& p, double altitude_m) {
  return {0.0, 0.0, p.bottom_radius_m + altitude_m};
}

}  // namespace nph::atmosphere
