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

/// ∛x for x in [2⁻¹⁰⁰⁰, 2¹⁰⁰⁰] (std::cbrt elsewhere), within 1 ulp of the true root like std::cbrt
/// (tested against the 64-bit-mantissa cbrtl), at a fraction of its cost: glibc's cbrt splits the
/// argument with frexp and scalbn, and was the conversion's largest single cost (8 % of `nephele
/// convert`'s CPU on the demo storm; issue 19). An exponent-thirding bit guess (error < 3.2 %),
/// two Halley steps y ← y(y³ + 2x)/(2y³ + x), each cubing the relative error (3e-2 → 3e-5 →
/// 3e-14), and a Newton step for the last bits.
double cubeRootPositive(double x);

}  // namespace nph::physics
