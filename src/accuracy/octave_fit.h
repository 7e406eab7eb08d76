#pragma once
// Fitting the multiple-scattering octave series (lighting/octave_series.h) to the path tracer
// (issue 12): `nephele-bench accuracy --fit-octaves`.
//
// For every accuracy scene the CPU reference of the eye pass (reference::marchCloudLayer's rays,
// step and sampling, no early termination) is marched once through the converged CPU deep light
// map (reference::DlmReference, default model), and each pixel keeps
//   * α (the ambient term's weight: Σ T_acc·(1 − T) = 1 − T_end), and
//   * the weights w = T_acc·(1 − T) of its samples binned by the sunlight's optical depth
//     τ = −ln I_DLM (log-spaced bins, linear interpolation), ice and water apart.
// The octave series' luminance of a pixel is then, for any a, b, c, N, a cheap sum over bins:
//   Y = Y_amb·α + Y_sun·Σ_n bⁿ Σ_bins [H_ice·4πp_HG(ψ; cⁿg_ice) + H_water·4πp_HG(ψ; cⁿg_water)]·e^{−aⁿτ}
// and a grid search over (a, b, c, N) minimises the mean over the scenes of the normalised squared
// error Σ_px (Y − Y_ref)² / Σ_px (Y_ref² + 0.01) against the path-traced truth. Not the per-pixel
// relMSE of image_error.h: with a noisy truth, relMSE's noisy denominators favour dark models,
// while the truth's zero-mean noise only adds a constant to a squared error (optimum unchanged). The binning (128 bins,
// 13 % wide in τ, weights split linearly between neighbours) changes e^{−aⁿτ} by well under 1 %; the winner is then
// re-rendered exactly by marchCloudLayer and measured with compareImages.
#include <string>
#include <vector>

#include "accuracy/accuracy_sweep.h"
#include "accuracy/image_error.h"
#include "lighting/octave_series.h"

namespace nph::accuracy {

struct OctaveFitSceneResult {
  std::string scene;
  ImageError single;      ///< today's model (one octave) vs the truth
  ImageError fitted;      ///< the fitted series vs the truth
  double march_ms = 0.0;  ///< CPU time of the fitted march (one thread of TBB's pool, for scale)
};

struct OctaveFitResult {
  lighting::OctaveSeries best;
  double objective = 0.0;  ///< mean normalised squared error over the scenes at the best (binned)
  /// The part of any objective that is the truth's own Monte Carlo noise (Σ σ²(Y_ref) normalised
  /// the same way): the floor of the objective for a perfect model.
  double objective_noise_floor = 0.0;
  std::vector<OctaveFitSceneResult> scenes;
  /// Objective at the best (a, c, N) for every b, and at the best (b, c, N) for every a (the
  /// valleys, to show how sharp the fit is).
  std::vector<std::pair<double, double>> along_b, along_a;
  /// The same with free non-negative octave weights (energy[0] = 1) in place of bⁿ, per (a, c):
  /// a linear least-squares problem, solved exactly for every (a, c) of the grid.
  lighting::OctaveSeries best_free;
  double objective_free = 0.0;
  std::vector<OctaveFitSceneResult> scenes_free;
};

/// Needs a current GL context (the DLM light space comes from the GPU builder's layout).
OctaveFitResult fitOctaveSeries(const SweepOptions& options);

/// Markdown table of the result (docs/accuracy.md).
std::string octaveFitMarkdown(const OctaveFitResult& result);

}  // namespace nph::accuracy
