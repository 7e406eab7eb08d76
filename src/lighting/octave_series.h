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
// p_v is the β_sca-weighted mix of Nes eq. 5.12 with Henyey–Greenstein lobes, a density over the
// sphere [1/sr] (docs/rendering.md "Conventions"). The GLSL and its C++ twin:
// glsl/common/cloud_light.glsl, lighting/cloud_light.h.
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

/// Σ_n bⁿ · I^{aⁿ} · p_v(ψ; cⁿ g) [1/sr]: the factor that multiplies E_sun at a sample whose DLM
/// sunlight is `sunlight` ∈ [0, 1]; `ice_weight` = β_ice / (β_ice + β_water) (Nes eq. 5.12). With
/// free weights (s.energy non-empty) they replace bⁿ; otherwise this is the eye pass's
/// octaveSeries() of glsl/common/cloud_light.glsl exactly (lighting/cloud_light.cpp).
double octaveSunFactor(const OctaveSeries& s, double sunlight, double cos_psi, double ice_weight, double g_ice,
                       double g_water);

}  // namespace nph::lighting
