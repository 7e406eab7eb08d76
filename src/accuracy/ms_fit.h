#pragma once
// Comparing multiple-scattering terms against the path tracer on the CPU reference (issue 12,
// third phase): `nephele-bench accuracy --compare-ms`.
//
// For every accuracy scene the CPU reference of the eye pass (reference::marchSamples, ½-voxel
// step, no early termination) is marched once through the converged CPU deep light map, and every
// pixel keeps the sums over its samples (weight w = T_acc·(1 − e^{−βΔ})) of the candidate terms,
// each per unit solar irradiance:
//   single      Σ w·p_v(ψ)·I_DLM                              octave 0 (Nes 2008 §5.2–5.4)
//   octaves     Σ w·Σ_{n=1,2} bⁿ·I^{aⁿ}/(4π)                   the fitted octaves (a 0.65, b 0.75, c 0)
//   two_stream  Σ w·(I₀ + g'μ_out·I₁)                           independent-column δ-Eddington
//               (lighting::twoStreamDiffuse; column depths of volume/column_depth.h)
//   column      Σ w·I^{aⁿ}/(4π) split into bins of the column's optical depth τ_a + τ_b
//               (octave weights as a function of the column: candidate (c) of the issue)
//   diffusion   Σ w·(φ + 3g·F·ω)/(4π) of the coarse diffusion volume (lighting/diffusion_volume.h;
//               issue 12's second approach), in 3-D and as the same grid's independent columns,
//               and two_stream × φ_3D/φ_1D; source the DLM's I or the column's beam, drift physical
//               or two_stream's (four configurations, docs/accuracy.md "Tenth session")
//   MC volume   Σ w·J of the Monte Carlo radiance volume (reference/mc_radiance_volume.h, fifteenth
//               session): photons traced like the path tracer's, orders ≥ 1 (with single scattering
//               from the exact beam, the DLM without its cone) or ≥ 2 (beside the DLM's single
//               scattering and forward lobe) tallied as spherical-harmonic moments on coarse cells,
//               the series truncated after l = 0 … 8 (docs/accuracy.md "Fifteenth session")
// A model's luminance is then Y = Y_sky + Y_sun·(single + Σ_j θ_j·term_j), linear in its free
// weights θ, which are fitted by least squares on the objective of octave_fit.h (mean over scenes of
// Σ ΔY² / Σ (Y_ref² + 0.01)). Per scene it reports the luminance bias Σ Y / Σ Y_ref − 1 and the
// relMSE of image_error.h (luminance only). The three models of the knob `multiple_scattering`
// are then rendered exactly by the CPU reference of the eye pass and measured with compareImages
// (relMSE, luminance bias, share of pixels off by > 2/255).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "accuracy/accuracy_sweep.h"
#include "accuracy/image_error.h"

namespace nph::accuracy {

struct MsModelScene {
  std::string scene;
  double luminance_bias = 0.0;
  double rel_mse = 0.0;
};

/// One multiple-scattering model of the eye pass rendered exactly (reference::marchCloudLayer, the
/// CPU twin of the GPU's term) and measured against the truth with compareImages.
struct MsRenderedScene {
  std::string scene, model;
  ImageError error;
  double march_ms = 0.0;  ///< CPU time of the march (TBB's pool, for scale)
};

struct MsModelResult {
  std::string model;
  std::vector<double> weights;  ///< fitted θ (empty: none free)
  double objective = 0.0;
  std::vector<MsModelScene> scenes;
};

struct MsComparison {
  std::vector<MsModelResult> models;      ///< the fits (luminance only)
  std::vector<MsRenderedScene> rendered;  ///< single, octaves and two_stream rendered exactly
  double objective_noise_floor = 0.0;     ///< the truth's own noise in the objective
  /// The Monte Carlo radiance volume's trace per scene [s] and its photons per scene.
  std::vector<std::pair<std::string, double>> mc_seconds;
  std::vector<std::pair<std::string, double>> gpu_mc_ms;  ///< the GPU radiance volume's build per scene
  std::uint64_t mc_photons = 0;
  std::string mc_cost_tally;  ///< the tally whose trace is timed (the first: --ms-mc-coarsen)
};

/// Needs a current GL context (the DLM light space comes from the GPU builder's layout).
MsComparison compareMultipleScattering(const SweepOptions& options);

/// Markdown tables of the comparison (docs/accuracy.md).
std::string msComparisonMarkdown(const MsComparison& comparison);

}  // namespace nph::accuracy
