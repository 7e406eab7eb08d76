#pragma once
// The light transport model of the deep light map (Nes 2008 §5.2.3, eq. 5.8-5.13) and its
// discretisation — one definition for the GPU builder (glsl/dlm/) and the CPU reference.
//
// Along a light ray, samples s_n = n·Δ (n = 0 … N, Δ = step_m) with I_0 = 1 (sunlight entering the
// fitted box). The step n → n+1 sees the extinction β = β_ice + β_water at its midpoint and the
// step transmittance T = exp(−β·Δ). Unscattered light is kept (eq. 5.8), and of the scattered
// fraction (1 − T) the share CP(θ/4) scattered within the central cone stays on the ray
// (eq. 5.9, 5.13):
//     I_{n+1} = I_n · [T + (1 − T)·CP(θ/4)] + P_{n+1}
// where P is the peripheral forward scattering (eq. 5.10) added by passes 2-3 from the scatter
// map (0 in pass 1). Exact solution for a homogeneous slab of thickness d = N·Δ in pass 1:
//     I(d) = [e^{−βΔ} + (1 − e^{−βΔ})·CP(θ/4)]^N,
// which converges for Δ → 0 to the continuum law I(d) = exp(−β·d·(1 − CP(θ/4))): the medium's
// effective extinction is reduced by the central forward-scattered share. The difference between
// the two is O(β²Δ·d·CP(1−CP)/2) — the discretisation term the GPU-vs-reference tests allow.
//
// Peripheral scattering (passes 2-3, §5.3.3): a low-resolution scatter map aligned with the DLM
// (every `scatter_downsample` texels per side, slices every `scatter_slice_steps` steps) carries
// the peripheral light P. Slice by slice, each cell takes the average light I = I_c + P of its four
// neighbours (±1 cell along u and v) in the previous slice — four equally spaced samples around
// the ray — and adds their share (1 − T_slice)·[CP(θ/2) − CP(θ/4)], where T_slice is the cell's own
// transmittance over the slice; P itself is attenuated like central light:
//     P_k = P_{k−1}·[T + (1 − T)·CP(θ/4)] + avg4(I_c + P)_{k−1}·(1 − T)·(CP(θ/2) − CP(θ/4)).
// Pass 3 re-marches every DLM texel adding P (trilinear from the scatter map) to the central
// light before compression, so the ε bound holds for the final function. I = min(I_c + P, 1):
// the model hands a cloud's peripheral share to its neighbours without taking it from the cloud's
// own central light, so beside a bright cloud edge I_c + P could exceed the unobstructed sun.
#include <algorithm>
#include <cstdint>
#include <string>

#include "lighting/light_space.h"

namespace nph::lighting {

struct DlmSettings {
  double epsilon = 0.01;            ///< max |I_stored − I_sampled| per texel (ε, Nes §5.3.4)
  double step_voxels = 0.5;         ///< Δ as a fraction of the smallest voxel side
  double texel_voxels = 1.0;        ///< DLM texel size as a multiple of the smallest horizontal voxel side
  int max_texels = 1024;            ///< per side of the map
  int max_nodes = 32;               ///< node budget per texel
  int max_epsilon_doublings = 4;    ///< overflow rule: retry overflowed texels with 2ε, 4ε, ...
  double forward_angle_deg = 20.0;  ///< θ: the forward-scattering cone (Nes §5.2.3)
  double cornette_shanks_g = 0.9;   ///< asymmetry of the transport phase (Cornette–Shanks)
  /// The beam's forward peak per medium (issue 12, twelfth session): the share f of each step's
  /// scattered light the beam keeps, f_ice for β_ice and f_water for β_water, mixed by β at the
  /// step (Nes 2008 eq. 5.12's weights). Negative: Nes' cone, CP(θ/4) of the Cornette–Shanks
  /// transport phase for both media.
  double forward_peak_ice = -1.0;
  double forward_peak_water = -1.0;
  bool peripheral = true;       ///< passes 2-3 (scatter map)
  int scatter_downsample = 4;   ///< scatter-map cell = this many DLM texels per side
  int scatter_slice_steps = 4;  ///< scatter-map slice = this many steps Δ (at least; below)
  /// ... and at least this fraction of the scatter cell's width (scatterSliceSteps). The slices
  /// follow Δ, i.e. the smallest (on model grids the vertical) voxel side, the cells the horizontal
  /// spacing, so on a 3 km × 250 m grid a 4-step slice is 12–80× finer along the light than a cell
  /// is across it. At ½ (the default since the twenty-eighth session) the benchmark storm's map is
  /// as close to the finest map as with 4-step slices (mean error 0.045 against 0.048) and builds
  /// 2.6× faster; the slice's β is averaged over it (scatterSliceSamples) and pass 3 ends its runs
  /// where Ic + P reaches 1 (glsl/dlm/march.comp). docs/benchmarks.md "Scatter-map slice length".
  /// 0: the steps alone (Nes' slices).
  double scatter_slice_cells = 0.5;
  bool empty_space_skipping = true;  ///< skip empty occupancy bricks in pass 1/3
  /// Adaptive light step (issue 19; glsl/dlm/march.comp): up to this many steps Δ in one where the
  /// occupancy brick bounds β closely enough that the run stays within the ray's error budget
  /// (step_growth_budget·ε in I against the fixed step, summed along the ray). 1: the fixed step.
  int step_growth_max = 1;
  double step_growth_budget = 0.5;  ///< the budget as a fraction of ε
  /// Light cache (issue 19): after each build the map's sunlight is baked into a world volume of
  /// this many extinction voxels per cell along each axis (R16F, glsl/dlm/light_cache.comp), and
  /// the eye pass reads it with one trilinear fetch. 0: no cache, the eye pass evaluates the map
  /// per sample (the reference path). Not part of the map itself, but of what a build produces.
  double light_cache_voxels = 0.0;

  /// Fingerprint of everything that changes the map (part of the DLM cache key).
  std::string key() const;
};

/// CP(θ/4) and CP(θ/2) − CP(θ/4) for the settings' cone and Cornette–Shanks phase; the central
/// share per medium (forward_peak_ice/water, else CP(θ/4) for both).
struct ForwardFractions {
  double central = 0.0;
  double peripheral = 0.0;
  double central_ice = 0.0;
  double central_water = 0.0;
  /// The central share of a step whose extinction is β_ice/β = ice_weight.
  double centralAt(double ice_weight) const { return central_water + (central_ice - central_water) * ice_weight; }
};
ForwardFractions forwardFractions(const DlmSettings& settings);

/// The scatter map's slice in steps Δ of `step_m`: the least even number ≥ scatter_slice_steps
/// whose slice is at least scatter_slice_cells × the cell's narrower side (scatter_downsample
/// texels of `light_space`). The GPU builder (which may lengthen it further to fit the 3-D texture
/// limit) and the CPU reference (reference::DlmReference) both slice so. Idempotent: an effective
/// value passed back in is kept.
int scatterSliceSteps(const DlmSettings& settings, const LightSpace& light_space, double step_m);

/// The β samples a scatter-map slice of `slice_steps` steps Δ averages for its transmittance: one
/// per kScatterSampleSteps steps (64 at most), so a long slice (scatter_slice_cells) sees a thin
/// layer that a single sample at its middle would miss (PassesTest.ShadowMatte…: clear ground
/// beside a 2 km slab at 0.975). One for slices up to 16 steps: Nes' one sample at the middle.
/// One per 16 steps: the benchmark storm's map error as with one per 4 or 8, a quarter of pass 2's
/// look-ups (docs/benchmarks.md "Scatter-map slice length").
inline constexpr int kScatterSampleSteps = 16;
inline int scatterSliceSamples(int slice_steps) {
  return std::clamp((slice_steps + kScatterSampleSteps - 1) / kScatterSampleSteps, 1, 64);
}

/// Per-step factor of pass 1: T + (1 − T)·CP(θ/4).
inline double centralStepFactor(double transmittance, double centralFraction) {
  return transmittance + (1.0 - transmittance) * centralFraction;
}

}  // namespace nph::lighting
