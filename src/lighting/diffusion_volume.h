#pragma once
// A coarse diffusion volume of multiply-scattered sunlight (issue 12, item 1, second approach:
// "a coarse 3-D grid where the sunlight already attenuated by the DLM is the source and a few
// dozen iterations of a diffusion solver give the isotropic multiply-scattered radiance"). Nes
// 2008 §5.2.3 names the diffuse light the deep light map lacks; §5.4 its limit; Muth 2026 §3.4.6
// asks for a multiple-scattering term. The independent column (twoStreamDiffuse,
// glsl/common/cloud_light.glsl) solves the same P1 equations in 1-D; this grid lets the light
// move sideways: thin cloud beside thick cloud, towers losing light through their sides.
//
// Frame: the data's (unexaggerated) metres. Height exaggeration keeps the data's optical depth
// along every path (volume/volume_frame.h opticalDepthScale), so in the data the medium is the
// data's β and only the directions are distorted: light scattered evenly in the exaggerated world
// travels mostly horizontally in the data. The diffusion is therefore anisotropic, D_i = a_i/σ_tr,
// with a = (a_h, a_h, a_z), a_z = ⟨d_z'²⟩ = twoStreamSunFrame(…).z / 3 and a_h = (1 − a_z)/2
// (1/3 each at true scale), σ_tr = (1 − g)·β (δ-Eddington: (1 − g')(1 − g²) = 1 − g).
//
// Equations (P1 with the δ-Eddington forward peak left in the beam, albedo 1, per unit solar
// irradiance E = 1; Joseph, Wiscombe & Weinman 1976 in 3-D):
//   ∇·F + σ_a·φ = S,   S = (1 − g²)·β·B·I,   σ_tr·F_i = q_i·S·Ω₀_i − a_i·∂_iφ,
// where I is the deep light map's sunlight (its forward peak kept), B = μ_w/μ₀ the beam of the
// exaggerated world (twoStreamSunFrame .y) and Ω₀ the beam's direction in the data. The first
// moment of the radiance equation gives ∇·(a·φ) for the second moment of a radiance that is
// isotropic in the world, and q_i = g' = g/(1 + g) (the first-scattered light's forward drift):
// `DiffusionDrift::Physical`. The eye pass's two_stream term (twoStreamDiffuse) keeps the
// particular solution of the unexaggerated slab when it slows the vertical diffusion, which is
// the same column with q_i = 3a_i − 1 + g' (upward drift at ×8): `DiffusionDrift::TwoStream`
// reproduces it exactly (tests/lighting/diffusion_volume_test.cpp). At true scale (a_i = 1/3)
// the two agree. In a column (1-D) with ds = 3a_z, k = (1 − g')/ds and K = k + q_z/ds the solution is
//   I₁ = ¾F·μ₀·e^{−τ/μ₀} + C₁,   I₀ = k·C₁·τ − ¾F·μ₀²·K·e^{−τ/μ₀} + C₂ (φ = 4π·I₀, F_z = 4π/3·I₁)
// with K = 1/ds (physical) or 1 (two_stream's). Boundaries: vacuum with Marshak's condition (no
// diffuse light enters: φ_b = 2·F_out) on every face of the grid, the ground included — the
// two-stream column's conditions. The radiance a sample scatters towards a direction ω (data
// frame) is the source function (φ + 3·g·F·ω)/(4π). Write G_i = q_i·S/σ_tr·Ω₀_i and D_i = a_i/σ_tr.
//
// Discretisation: cell-centred finite volumes. Across a face between cells c and n along axis i
// the half-cell resistances r = τ_i/(2·a_i) (τ_i = σ_tr·h_i, the cell's transport depth along i)
// add up to R; the face flux c → n is (φ_c − φ_n + r_c·G_c + r_n·G_n)/R (G along c → n) (exact for a piecewise
// constant medium); a vacuum face is a neighbour with r = 2, φ = 0, G = 0. The system is symmetric
// positive definite (a weighted graph Laplacian with Marshak leaks), solved by conjugate gradients
// with a Jacobi preconditioner. Clear air has σ_tr = 0 and so R = 0 (P1 light crosses a gap
// freely, then leaks at the grid's faces); R is floored at `min_resistance` to keep it finite.
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "volume/extinction_volumes.h"
#include "volume/volume_frame.h"

namespace nph::lighting {

/// The medium and source of one diffusion problem on a regular grid (data metres).
struct DiffusionProblem {
  glm::ivec3 cells{0};
  glm::dvec3 cell_m{1.0};                         ///< cell size in the data frame [m]
  glm::dvec3 anisotropy{1.0 / 3.0};               ///< a_i (1/3 each: isotropic diffusion)
  std::vector<double> sigma_tr;                   ///< (1 − g)·β per cell [1/m]
  std::vector<double> sigma_a;                    ///< absorption per cell [1/m] (empty: 0, clouds)
  std::vector<double> source;                     ///< S per cell [1/m per unit E]
  std::vector<glm::dvec3> drift;                  ///< G per cell [per unit E] (empty: 0)
  std::size_t index(int i, int j, int k) const {  ///< x fastest, then y, then z (bottom up)
    return (std::size_t(k) * std::size_t(cells.y) + std::size_t(j)) * std::size_t(cells.x) + std::size_t(i);
  }
  std::size_t size() const { return std::size_t(cells.x) * std::size_t(cells.y) * std::size_t(cells.z); }
};

struct DiffusionSolveOptions {
  bool horizontal = true;        ///< false: independent columns (the 1-D problem of the same grid)
  double min_resistance = 1e-3;  ///< floor of a face's resistance R (clear air)
  /// Passes of flux-limited diffusion (Levermore & Pomraning 1981) after the linear solve, each
  /// with the faces' diffusion limited by the previous pass's φ (0: plain P1 diffusion).
  int flux_limited_passes = 0;
  int max_iterations = 2000;
  double tolerance = 1e-8;  ///< on ‖r‖/‖b‖
};

struct DiffusionSolution {
  std::vector<double> fluence;   ///< φ per cell [per unit E]
  std::vector<glm::dvec3> flux;  ///< F per cell: the mean of its two faces per axis [per unit E]
  int iterations = 0;            ///< conjugate-gradient iterations, summed over the passes
  double relative_residual = 0.0;
};

/// Solves the finite-volume system of the header (conjugate gradients, Jacobi preconditioner).
DiffusionSolution solveDiffusion(const DiffusionProblem& problem, const DiffusionSolveOptions& options);

/// The first-scattered light's drift along the beam under height exaggeration (see above).
enum class DiffusionDrift { Physical, TwoStream };

/// Options of the volume built from a scene.
struct DiffusionVolumeOptions {
  DiffusionDrift drift = DiffusionDrift::Physical;
  int coarsen_xy = 4;  ///< fine voxels per coarse cell horizontally (¼ of the extinction grid)
  int coarsen_z = 2;   ///< and vertically
  double g_ice = 0.75, g_water = 0.85;
};

/// The coarse problem of a scene: σ_tr and S averaged over the fine voxels of each coarse cell
/// (S and G from `sunlight(world point, g)` — the DLM's I — at every fine voxel centre), the data
/// frame's cell size, a and Ω₀ from the sun's world direction `to_sun` and the frame's exaggeration.
DiffusionProblem diffusionProblemFor(const ExtinctionVolumes& volumes, const volume::VolumeFrame& frame,
                                     const glm::dvec3& to_sun,
                                     const std::function<double(const glm::dvec3&, double)>& sunlight,
                                     const DiffusionVolumeOptions& options);

/// A solved diffusion volume, sampled at world points (trilinear between coarse cell centres,
/// clamped to the edge).
struct DiffusionVolume {
  DiffusionProblem problem;
  DiffusionSolution solution;
  volume::VolumeFrame frame;  ///< the fine grid's world frame
  glm::ivec3 coarsen{4, 4, 2};

  /// (φ, F) at a world point.
  double fluenceAt(const glm::dvec3& world_m) const;
  glm::dvec3 fluxAt(const glm::dvec3& world_m) const;
  /// The radiance the diffuse field scatters towards the eye [1/sr per unit E]:
  /// (φ + 3·g·F·ω)/(4π), ω the direction towards the eye in the data frame (unit).
  double radianceAt(const glm::dvec3& world_m, const glm::dvec3& to_eye_data, double g) const;
};

}  // namespace nph::lighting
