#pragma once
// Effective radius from mass and number (two-moment microphysics, e.g. WRF Thompson QN*).
//
// Assume a gamma size distribution of sphere diameters D, n(D) = N0 D^μ exp(-λD), particles of
// bulk density ρ_p. With q [kg/kg] and N [1/kg] the mass and number per kg of air (the air
// density cancels):
//   N = N0 Γ(μ+1) / λ^(μ+1),   q = (π/6) ρ_p N0 Γ(μ+4) / λ^(μ+4)
//   ⇒ λ³ = (π/6) ρ_p (N/q) (μ+1)(μ+2)(μ+3).
// In the geometric-optics limit the extinction of the distribution is that of spheres of the
// effective radius r_eff = ½ M3/M2 = (μ+3) / (2λ) (Hansen & Travis 1974): eq. 5.3 of Nes 2008
// is then exact for the whole distribution, β = 3 ρ_air q / (2 ρ_p r_eff).
namespace nph::physics {

/// r_eff [m] for mass q [kg/kg] and number N [1/kg]; returns `fallback_m` when q or N is not
/// positive (no information), else the result clamped to [min_m, max_m].
double effectiveRadiusFromNumber(double q_kg_per_kg, double number_per_kg, double particle_density_kg_per_m3,
                                 double gamma_shape, double fallback_m, double min_m, double max_m);

}  // namespace nph::physics
