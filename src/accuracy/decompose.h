#pragma once
// Where the remaining bias comes from (issue 12, twelfth session): `nephele-bench accuracy
// --decompose`. The truth and the renderer are split into the same parts and compared part by part,
// as mean cloud-layer luminance over the image (the "luminance bias"):
//
//   part                       truth (reference/path_tracer.h)          renderer (CPU twin of the eye pass)
//   sky light                  sun off, every order                     Σ w·½(L_above·T_d(τ_up) + L_below·T_d(τ_down))
//   sun, order 1               sun only, max_events = 1                 Σ w·E·p_v(ψ)·e^{−τ_sun}: the DLM without its
//                                                                       forward cone (θ = 0, no scatter map)
//   sun, order 2               sun only, max_events = 2, − order 1      —
//   sun, orders ≥ 2            full − sky − order 1                     the DLM's forward cone Σ w·E·p_v·(I_DLM −
//   e^{−τ})
//                                                                       + the multiple-scattering term (two_stream)
//   total                      the cached full truth                    all of the above (= the default image)
//
// Order 1 and the sky should agree by construction (Nes 2008 §5.2.2: single scattering of the
// direct beam is exact in the model; the sky term is a model, docs/light-transport.md); orders ≥ 2
// are the deep light map's forward scattering (Nes §5.2.3, its stated limit) and the two-stream
// term. The renderer is the CPU reference of the eye pass (reference::marchSamples at ⅛ voxel, no
// early termination) through the converged CPU deep light map (convergedLight), so the comparison
// holds no GPU discretisation. The truth's parts are traced at `decompose_spp` into the same cache
// (their image means need few samples: 14 400 pixels average the noise; the standard error of each
// mean is reported).
#include <string>
#include <vector>

#include "accuracy/accuracy_sweep.h"

namespace nph::accuracy {

struct DecomposedPart {
  std::string name;
  double truth = 0.0;     ///< mean luminance over the image
  double truth_se = 0.0;  ///< standard error of that mean (Monte Carlo)
  double model = 0.0;     ///< the renderer's (NaN: no counterpart)
};

struct SceneDecomposition {
  std::string scene;
  std::vector<DecomposedPart> parts;
};

/// Needs a current GL context (the DLM light space comes from the GPU builder's layout).
std::vector<SceneDecomposition> decomposeBias(const SweepOptions& options, int part_spp);

/// Markdown table (docs/accuracy.md "Twelfth session").
std::string decompositionMarkdown(const std::vector<SceneDecomposition>& scenes);

}  // namespace nph::accuracy
