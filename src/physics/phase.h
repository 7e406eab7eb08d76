#pragma once
// Scattering phase functions of cloud particles (Nes 2008 §2.2.5, §5.2.4) and their cumulative
// phase (Nes 2008 §5.2.3, eq. 5.9-5.10).
//
// Convention: a phase function p(cos ψ) is a probability density over the sphere of outgoing
// directions, in 1/sr, normalised as ∫_{4π} p dΩ = 1 (the 1/(4π) convention of Nes eq. 2.9; an
// isotropic scatterer has p = 1/(4π)). ψ is the scattering angle between the direction the light
// travels before and after the event: ψ = 0 is straight on (forward), ψ = π is back to the source.
//
// Cumulative phase (Nes §5.2.3, "the integrated phase function"): the fraction of the scattered
// energy that leaves within angle θ of the forward direction,
//     CP(θ) = 2π ∫_0^θ p(cos ψ) sin ψ dψ = 2π ∫_{cos θ}^1 p(μ) dμ,      CP(0) = 0, CP(π) = 1.
// Nes' light transport uses CP(θ/4) for the central and CP(θ/2) − CP(θ/4) for the peripheral
// forward-scattered light (eq. 5.9, 5.10), with the Cornette–Shanks phase (§5.2.4).
//
// Models:
//  * Henyey–Greenstein (Henyey & Greenstein 1941; Nes eq. 2.9):
//        p_HG(μ) = 1/(4π) · (1 − g²) / (1 + g² − 2gμ)^{3/2},       mean cosine ⟨μ⟩ = g.
//    CP has a closed form (derived in phase.cpp) and the inverse-CDF sample is exact.
//  * Cornette–Shanks (Cornette & Shanks 1992, Applied Optics 31(16) 3152, eq. 8): HG multiplied by
//    a Rayleigh-like (1 + μ²) term, which gives a more realistic side/back lobe,
//        p_CS(μ) = 1/(4π) · 3(1 − g²) / (2(2 + g²)) · (1 + μ²) / (1 + g² − 2gμ)^{3/2}.
//    g = 0 is Rayleigh, (3/(16π))(1 + μ²). Note the mean cosine of CS is NOT g:
//    ⟨μ⟩ = 3g(4 + g²) / (5(2 + g²)) (Cornette & Shanks 1992, eq. 9), e.g. 0.924 for g = 0.9.
//    CP is integrated numerically and tabulated (CumulativePhaseTable, error < 1e-7 checked at
//    build); sampling is exact by rejection from HG with the same g (acceptance (1 + μ²)/2).
//
// Defaults (documented, overridable by every user):
//  * eye phase, water droplets: HG g = 0.85 — asymmetry parameter of cloud droplets with effective
//    radius ≈ 10 µm in the visible is 0.85-0.87 (Hansen & Travis 1974, Space Sci. Rev. 16, Fig. 12;
//    Liou 2002, "An Introduction to Atmospheric Radiation", §5.2). Issue 5's renderer default.
//  * eye phase, ice crystals: HG g = 0.75 — hexagonal columns/plates/aggregates give g ≈ 0.74-0.80
//    (Macke, Mueller & Raschke 1996, J. Atmos. Sci. 53; Yang et al. 2013). Nes §5.2.4 (after
//    Wendling et al. 1979): ice has more side and back scattering than water.
//  * transport phase (Nes §5.2.3-5.2.4: Cornette–Shanks for the DLM): CS g = 0.9. With this g,
//    CP(10°) ≈ 0.54 and CP(30°) ≈ 0.88; the ~90 % within 10° of Nes Fig. 5.5 (Riley et al. 2004)
//    needs the diffraction peak of a true Mie function, which neither HG nor CS at g ≈ 0.9 has.
#include <memory>
#include <vector>

namespace nph::physics {

enum class PhaseModel { HenyeyGreenstein, CornetteShanks };

/// Documented defaults (see the header comment for the sources).
inline constexpr double kWaterEyeAsymmetry = 0.85;  ///< HG g of cloud droplets
inline constexpr double kIceEyeAsymmetry = 0.75;    ///< HG g of ice crystals
inline constexpr double kTransportAsymmetry = 0.9;  ///< Cornette–Shanks g for light transport

/// p_HG(cos ψ) [1/sr]; g in (−1, 1).
double henyeyGreenstein(double cos_psi, double g);
/// p_CS(cos ψ) [1/sr]; g in (−1, 1).
double cornetteShanks(double cos_psi, double g);
/// Closed-form CP(θ) of Henyey–Greenstein; θ in [0, π] (clamped).
double henyeyGreensteinCumulative(double theta_rad, double g);
/// cos ψ of an HG-distributed scattering angle by inverting its CDF; u uniform in [0, 1).
double sampleHenyeyGreenstein(double u, double g);

/// A phase function: model + asymmetry parameter g.
struct PhaseFunction {
  PhaseModel model = PhaseModel::HenyeyGreenstein;
  double g = 0.0;

  /// p(cos ψ) [1/sr].
  double eval(double cos_psi) const;
  /// Exact sample of cos ψ. `next` returns independent uniforms in [0, 1); it is called once for
  /// HG; for CS each try takes two and is accepted with probability (1 + ⟨μ²⟩_HG)/2 = (2 + g²)/3
  /// (⟨μ²⟩_HG = (1 + 2g²)/3), i.e. 1.5 tries on average at g = 0 and 1.07 at g = 0.9.
  template <class Uniform>
  double sampleCos(Uniform&& next) const {
    if (model == PhaseModel::HenyeyGreenstein) return sampleHenyeyGreenstein(next(), g);
    // Rejection from HG: p_CS / p_HG = 3(1 + μ²)/(2(2 + g²)) ≤ 3/(2 + g²); accept with (1 + μ²)/2.
    for (;;) {
      const double mu = sampleHenyeyGreenstein(next(), g);
      if (2.0 * next() <= 1.0 + mu * mu) return mu;
    }
  }

  static PhaseFunction waterEyeDefault() { return {PhaseModel::HenyeyGreenstein, kWaterEyeAsymmetry}; }
  static PhaseFunction iceEyeDefault() { return {PhaseModel::HenyeyGreenstein, kIceEyeAsymmetry}; }
  static PhaseFunction transportDefault() { return {PhaseModel::CornetteShanks, kTransportAsymmetry}; }
};

/// CP(θ) of any PhaseFunction, integrated numerically (8-point Gauss–Legendre per interval of
/// dCP/dθ = 2π p(cos θ) sin θ) on a uniform θ grid over [0, π] and interpolated with cubic Hermite
/// splines using the exact derivative. The grid is doubled until the interpolation error, checked
/// against the integral at every interval midpoint, is below `tolerance` (default 1e-7).
/// CP(π) is not renormalised: |CP(π) − 1| is the quadrature error (< 1e-12 for |g| ≤ 0.99).
class CumulativePhaseTable {
 public:
  explicit CumulativePhaseTable(PhaseFunction phase, double tolerance = 1e-7);
  /// CP(θ) [fraction]; θ clamped to [0, π].
  double operator()(double theta_rad) const;
  /// The tabulated nodes CP(i·π/(n−1)), i = 0..n−1 (e.g. for a 1D texture upload).
  const std::vector<double>& nodes() const { return cp_; }
  /// max over interval midpoints of |interpolated − integrated| found at build time.
  double maxInterpolationError() const { return max_error_; }
  const PhaseFunction& phase() const { return phase_; }

 private:
  double derivative(double theta_rad) const;  // dCP/dθ
  PhaseFunction phase_;
  double h_ = 0.0;           // node spacing [rad]
  std::vector<double> cp_;   // CP at nodes
  std::vector<double> dcp_;  // dCP/dθ at nodes
  double max_error_ = 0.0;
};

/// CP(θ) of `phase`: closed form for HG; for CS a table built once per distinct g and cached
/// (thread-safe). Use CumulativePhaseTable directly in hot loops.
double cumulativePhase(const PhaseFunction& phase, double theta_rad);

/// Nes 2008 eq. 5.12 (= eq. 2.10): the phase of a voxel holding ice and water is the mean of the
/// two phase functions weighted by their scattering coefficients,
///     P_v(ψ) = (P_ice(ψ) β_sca^ice + P_water(ψ) β_sca^water) / (β_sca^ice + β_sca^water).
/// With single-scattering albedo 1 (Nes §5.2.2) β_sca = β_ext, so the extinction volumes can be
/// passed directly. Sampling the mixture = picking ice with probability β_ice/(β_ice + β_water)
/// and sampling its phase function (what the path tracer does per collision).
struct PhaseMix {
  PhaseFunction ice = PhaseFunction::iceEyeDefault();
  PhaseFunction water = PhaseFunction::waterEyeDefault();

  /// Weight of the ice phase in [0, 1]; 0.5 where both coefficients are 0 (any value would do).
  static double iceWeight(double ice_sca_per_m, double water_sca_per_m) {
    const double sum = ice_sca_per_m + water_sca_per_m;
    return sum > 0.0 ? ice_sca_per_m / sum : 0.5;
  }
  /// P_v(cos ψ) [1/sr] (eq. 5.12).
  double eval(double cos_psi, double ice_sca_per_m, double water_sca_per_m) const {
    const double w = iceWeight(ice_sca_per_m, water_sca_per_m);
    return w * ice.eval(cos_psi) + (1.0 - w) * water.eval(cos_psi);
  }
};

}  // namespace nph::physics
