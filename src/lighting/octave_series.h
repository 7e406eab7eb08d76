#pragma once
// Multiple scattering of sunlight as an octave series (issue 12), after Wrenninge, Kulla &
// Lundqvist 2013, "Oz: the great and volumetric" (SIGGRAPH talk; their §"multiple scattering
// approximation"), used for clouds by Hillaire 2016 ("Physically based sky, atmosphere and cloud
// rendering in Frostbite", §5.9.3) and Schneider 2015/2017 (Nubis); Muth 2026 §3.4.6 lists it as the
// multiple-scattering approximation for this renderer.
//
// The deep light map gives at a point the sunlight I that survived the way in, T(τ) plus the
// forward-scattered central and peripheral share (Nes 2008 §5.2.3). Single scattering towards the
// eye is E·I·p(ψ). Light scattered more than once has travelled further but is less forward
// peaked and less attenuated per metre; the series adds octaves n = 1, 2, … of the same look-up
// with the optical depth, the energy and the phase anisotropy scaled geometrically:
//     F(I, ψ) = Σ_{n=0}^{N−1} bⁿ · I^{aⁿ} · p_v(ψ; cⁿ·g_ice, cⁿ·g_water)
// where I^{aⁿ} = T(aⁿ·τ) for pure attenuation (T(τ) = e^{−τ}, so T(aτ) = T(τ)^a) — the same DLM
// value, no extra look-up. n = 0 is today's single-scattering term exactly, and a, b, c ∈ (0, 1].
// Wrenninge et al. guessed a, b, c by eye (a ≈ b ≈ 0.5); here they are FITTED to the path tracer on
// the accuracy scenes (src/accuracy/octave_fit.h, docs/accuracy.md), not guessed.
// p_v is the β_sca-weighted mix of Nes eq. 5.12 with Henyey–Greenstein lobes; the functions return
// 4π·p (1 for isotropic scattering), the eye pass's convention.
#include <algorithm>
#include <cmath>
#include <vector>

namespace nph::lighting {

struct OctaveSeries {
  int octaves = 1;                ///< N; 1 = single scattering only (no multiple-scattering term)
  double extinction_scale = 0.5;  ///< a: optical depth of octave n is aⁿ·τ
  double energy_scale = 0.5;      ///< b: weight of octave n is bⁿ
  double anisotropy_scale = 0.5;  ///< c: HG asymmetry of octave n is cⁿ·g
  /// Optional free weights of octaves 0 … N−1 in place of bⁿ (then N = energy.size()); fitted by
  /// non-negative least squares with energy[0] = 1 (src/accuracy/octave_fit.h).
  std::vector<double> energy;
};

/// Henyey–Greenstein times 4π (1 for isotropic).
inline double hg4pi(double cos_psi, double g) {
  const double g2 = g * g;
  return (1.0 - g2) / std::pow(std::max(1.0 + g2 - 2.0 * g * cos_psi, 1e-6), 1.5);
}

/// Σ_n bⁿ · I^{aⁿ} · 4π·p_v(ψ; cⁿ g): the factor that multiplies E_sun at a sample whose DLM
/// sunlight is `sunlight` ∈ [0, 1]; `ice_weight` = β_ice / (β_ice + β_water) (Nes eq. 5.12).
inline double octaveSunFactor(const OctaveSeries& s, double sunlight, double cos_psi, double ice_weight,
                              double g_ice, double g_water) {
  double sum = 0.0, energy = 1.0, depth = 1.0, aniso = 1.0;
  const int octaves = s.energy.empty() ? s.octaves : int(s.energy.size());
  for (int n = 0; n < octaves; ++n) {
    if (!s.energy.empty()) energy = s.energy[std::size_t(n)];
    const double light = n == 0 ? sunlight : (sunlight > 0.0 ? std::pow(sunlight, depth) : 0.0);
    const double phase = ice_weight * hg4pi(cos_psi, aniso * g_ice) + (1.0 - ice_weight) * hg4pi(cos_psi, aniso * g_water);
    sum += energy * light * phase;
    energy *= s.energy_scale;
    depth *= s.extinction_scale;
    aniso *= s.anisotropy_scale;
  }
  return sum;
}

}  // namespace nph::lighting
