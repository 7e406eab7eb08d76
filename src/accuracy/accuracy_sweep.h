#pragma once
// The knob sweep of `nephele-bench accuracy` (issue 6). For every standard scene and every variant
// (the default settings, one knob at a time around them, and the quality presets) it builds the
// deep light map and ray casts the scene `runs` times on the GPU, keeps the median of each, and
// measures the cloud layer's error against
//   (a) the path-traced ground truth (ground_truth.h): the model's bias plus discretisation, and
//   (b) the CPU reference of the same approximation, converged: the variant's light-transport
//       model (cone, scatter map) integrated by reference::DlmReference without compression at
//       1/8-voxel sub-steps and the eye pass marched at 1/8 voxel without early termination —
//       so (b) is the discretisation, compression and early-termination error of the setting.
// The GPU renders without jitter (pixel-centre rays, like both references), so every number is
// deterministic up to timing.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "accuracy/ground_truth.h"
#include "accuracy/image_error.h"
#include "lighting/dlm_model.h"
#include "lighting/knobs.h"
#include "reference/dlm_reference.h"
#include "render/dlm/volume_textures.h"
#include "render/raycast/cloud_renderer.h"
#include "scene/scene_file.h"

namespace nph::accuracy {

struct Variant {
  std::string knob;   ///< "default", a knob of lighting/knobs.h ("step_voxels", "dlm_epsilon", ...), a
                      ///< transport-model setting ("scatter_downsample", "forward_angle_deg") or "preset"
  std::string value;  ///< the knob's value as text
  lighting::DlmSettings dlm;
  render::RenderSettings render;
};

/// The knobs of a QualitySettings preset as DLM and ray-caster settings (jitter off).
Variant variantOf(const lighting::QualitySettings& quality);
/// The converged CPU deep light map of `dlm`'s transport model for scene `sc` (no compression,
/// 1/8-voxel sub-steps, the GPU's default light space; needs a current GL context for the layout).
/// `texel_voxels`: the light space's texel size (the default map's 1 voxel; finer to see what the
/// texel size itself costs, `--decompose --reference-dlm-texel`).
std::unique_ptr<reference::DlmReference> convergedLight(const lighting::DlmSettings& dlm,
                                                        const render::VolumeTextures& tex, const AccuracyScene& sc,
                                                        double texel_voxels = lighting::DlmSettings{}.texel_voxels);
/// The sweep's default variant: the broadcast preset with the DLM's own budgets (jitter off).
Variant defaultVariant();
/// default, the one-knob-at-a-time sweep and the three presets; `quick` keeps two values a knob.
std::vector<Variant> sweepVariants(bool quick);

struct SweepOptions {
  int width = 160;
  int height = 90;
  bool quick = false;
  int runs = 3;  ///< timed repetitions (median)
  GroundTruthSettings ground_truth;
  std::string out_dir = "accuracy";
  std::string cache_dir;      ///< ground-truth cache; default <out_dir>/ground-truth
  std::string scene_filter;   ///< substring of scene names to run (empty = all)
  std::string knob_filter;    ///< substring of knob names to run ("preset", "epsilon", ...; empty = all)
  bool write_images = false;  ///< PNGs of the ground truth and every variant
  /// --compare-ms: the coarse diffusion volume's cells (fine voxels per cell horizontally and
  /// vertically) and its faces' resistance floor (lighting/diffusion_volume.h).
  int diffusion_coarsen_xy = 4, diffusion_coarsen_z = 2;
  double diffusion_min_resistance = 1e-3;
  int diffusion_flux_limited_passes = 0;  ///< flux-limited diffusion passes (0: plain P1)
  /// --compare-ms: photons per scene of the Monte Carlo radiance volume (reference/mc_radiance_volume.h).
  std::uint64_t mc_photons = 1 << 16;
  /// --compare-ms: the cells of the Monte Carlo volume's first tally (orders >= 1, l <= 8).
  int mc_coarsen_xy = 4, mc_coarsen_z = 2, mc_subdivide_z = 1;
  /// --decompose: texel size of the converged CPU deep light maps, in voxels (default map: 1).
  double reference_dlm_texel_voxels = 1.0;
};

struct SweepRow {
  std::string scene, knob, value;
  double dlm_ms = 0.0, raycast_ms = 0.0;  ///< medians over the runs
  double dlm_mean_nodes = 0.0;
  int dlm_unbounded_texels = 0;
  ImageError vs_truth, vs_reference;
  double truth_truncated_share = 0.0;
  double coverage = 0.0;  ///< mean ground-truth alpha
};

/// The ground-truth cache folder of `options` (--cache, or OUT/ground-truth).
std::string groundTruthCacheDir(const SweepOptions& options);
/// The standard scenes at the options' size (generated data under OUT/scratch).
SceneSet sweepScenes(const SweepOptions& options);

/// Runs the sweep (needs a current GL context), logging progress. Writes nothing.
std::vector<SweepRow> runSweep(const SweepOptions& options);

/// √(rmse² − noise²): the RMSE with the ground truth's own Monte Carlo noise taken out.
double biasRmse(const ImageError& e);

/// CSV with a header line: the columns of SweepRow in order (csvColumns()).
void writeCsv(const std::vector<SweepRow>& rows, const std::string& path);
const std::vector<std::string>& csvColumns();

}  // namespace nph::accuracy
