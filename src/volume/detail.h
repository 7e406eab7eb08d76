#pragma once
// Procedural sub-grid detail (issue 13 item 2; Muth 2026 §3.3.1 "Sub-Grid Detail Synthesis";
// Thomann 2021 §4 for the noise volume): what the coarse model grid cannot resolve, synthesised at
// render time from a periodic noise volume (volume/noise.h) and per-voxel controls derived here.
// The rule itself — displacement and density factor — is glsl/common/detail.glsl, run by the
// shaders (glsl/dlm/volume.glsl extinctionAt) and, compiled as C++, by ExtinctionSampler: the DLM,
// the eye pass, the CPU reference ray marcher and the path tracer all see one detailed field.
//
// Knob `detail` (lighting/knobs.h): none = the data-true field, bit for bit as before; subtle =
// half amplitude and half displacement; full.
//
// Controls (RGBA8 at data resolution, GL_LINEAR; the CPU reads the same codes):
//   r  turbulence amplitude a_t = 0.25 + 0.75·s, s ∈ [0, 1] the largest available of
//        √(TKE / 5 m²s⁻²)   (Muth: σ_h = √(2/3·TKE), normalised against TKE = 5 m²s⁻²),
//        |W| / 2 m s⁻¹       (resolved vertical motion; WRF's TKE_PBL is zero above the boundary
//                             layer, where convective clouds still churn),
//      and where the source has neither (a .nph cache, a host's volume) the hydrometeor-gradient
//      proxy Σ_axes |β(+1) − β(−1)| / (2·max β of the 7-point stencil): large at cloud edges and
//      in sheared cells, 0 in uniform layers. The floor 0.25 stands for the sub-grid variability of
//      any cloud (without it, a stratiform deck under zero TKE would get no displacement at all).
//   g  convective weight, per column: where W is present, smoothstep(0.5, 3 m/s, the column's max
//      |W|) — convective cells are where the model resolves updrafts (this replaces Muth's TKE-based
//      weight and cumulonimbus bypass: WRF's TKE_PBL does not see deep convection, and a storm's
//      stratiform shield is as deep as its cells, 9 km in the coarse storm, so depth alone cannot
//      tell them apart). Without W, the proxy smoothstep(3, 7 km, condensate depth) ×
//      smoothstep(1.2, 2, τ_column / mean τ of the 5×5 columns around): a deep column that stands
//      out from its surroundings (condensate: β > 1e-5 /m, an optical depth of 0.01 per km).
//   b  cloud fraction (WRF CLDFRA, ICON clc) where present, else 1 (no acceptance).
//   a  core = β / the column's max β: 1 in the densest part (left dense), 0 at the edges (eroded).
//
// Scale: the noise is addressed in WORLD metres (fixed in space: a still scene is bit-identical
// frame to frame and an animation does not swim), one tile per P = 2·max(dx, dy) metres on every
// axis (dx, dy the model's column spacing in world metres): the coarsest lattice cell of the
// noise is half a column, the finest 1/16 — detail the grid cannot hold, and a column averages
// enough cells to keep its optical mass (docs/detail.md). The displacement noise has the period
// 2P. Displacement cap: ¼ column horizontally, min(¼ column, 1 layer) vertically, × the strength.
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "volume/extinction_volumes.h"
#include "volume/noise.h"
#include "volume/volume_frame.h"

namespace nph::volume {

enum class Detail { None = 0, Subtle = 1, Full = 2 };

/// Names in the order of the enum values (knob `detail`, scene files, docs).
inline constexpr std::array<std::string_view, 3> kDetailNames{"none", "subtle", "full"};

/// What the shaders and the CPU twin need besides the controls and the noise.
struct DetailParameters {
  Detail detail = Detail::None;
  double amplitude = 0.0;    ///< density modulation strength: 0, ½, 1
  glm::dvec3 period_m{1.0};  ///< world metres per noise tile (density noise)
  glm::dvec3 reach_m{0.0};   ///< displacement cap per axis [world m]
  int reach_voxels = 0;      ///< ceil of the cap in voxels: the occupancy's extra dilation
  bool on() const { return detail != Detail::None; }
};
DetailParameters detailParameters(Detail detail, const VolumeFrame& frame);

/// Advection of the noise with the model wind (issue 13 "temporally coherent: the noise is fixed in
/// the air mass — advected with the model wind (U, V) between timesteps"; Muth 2026 §3.3.1 builds
/// the detail per forecast hour and leaves the animation to future work, §5.2). Between two
/// timesteps the volume is the blend of both (docs/animation.md): the clouds the model moves
/// between them travel with the wind, and noise fixed in world space stays behind while they do.
/// Here the noise is read at x − u(x)·τ, u the horizontal model wind at x (U, V; W is left out:
/// 1–10 m/s in the cells' cores would cycle a tile vertically within minutes), τ the model time
/// since the phase's start — the "flow map" scheme of water rendering (two phases half a period
/// apart, each reset when its weight is 0, weights triangular in the phase): a spatially varying
/// wind stretches the noise by at most |∇u|·T, never without bound, and the noise is continuous in
/// time (the clock runs through the timestep blend and across timesteps). With a uniform wind each
/// phase is exactly the noise translated by u·τ; without a wind (a .nph cache, a host volume) the
/// noise is the world-fixed tile bit for bit (weight 1 on a phase with τ = 0).
/// Period: T = 30 min of model time — a 10 m/s wind moves a phase by 9 km (about a noise tile on a
/// 10-km grid) before it fades out, and a shear of 1 m/s per column stretches it by ≤ 1.8 km.
inline constexpr double kDetailFlowPeriod_s = 1800.0;
/// detail_clock_s of a timestep's time: seconds since 2000-01-01T00:00:00Z, 0 without a time.
double detailClock_s(const geo::OptionalUtcTime& time_utc);
/// The two phases at a clock: τ per phase [s] and phase a's weight (b's is 1 − it). φ = the clock
/// modulo T, in periods: τ_a = φ·T, τ_b = ((φ + ½) mod 1)·T, w_a = 1 − |2φ − 1| (0 where τ_a resets,
/// 1 where τ_b does). `has_wind` false: (0, 0, 1), the world-fixed noise.
struct DetailFlow {
  glm::dvec2 tau_s{0.0};
  double weight_a = 1.0;
};
DetailFlow detailFlow(double clock_s, bool has_wind);
/// The horizontal wind (U, V) at data resolution for the noise's advection, as uploaded (RG32F,
/// GL_LINEAR, GL_CLAMP_TO_EDGE); empty when the volumes carry no U and V.
struct DetailWind {
  int nx = 0, ny = 0, nz = 0;
  std::vector<float> uv;  ///< (u, v) per voxel, x fastest as ExtinctionVolumes
  bool empty() const { return uv.empty(); }
  /// GL_LINEAR with GL_CLAMP_TO_EDGE at continuous grid coordinates g (voxel centres at i + ½).
  glm::dvec2 at(const glm::dvec3& g) const;
};
DetailWind buildDetailWind(const ExtinctionVolumes& volumes);

/// The largest density factor ρ (detail.glsl): occupancy maxima and majorants scale by it.
inline constexpr double kMaxDetailDensity = 2.0;

/// Per-voxel controls, RGBA8 codes as uploaded (see above), x fastest as ExtinctionVolumes.
struct DetailControls {
  int nx = 0, ny = 0, nz = 0;
  std::vector<std::uint8_t> rgba;
  /// GL_LINEAR with GL_CLAMP_TO_EDGE at continuous grid coordinates g (voxel centres at i + ½).
  glm::dvec4 at(const glm::dvec3& g) const;
};
DetailControls buildDetailControls(const ExtinctionVolumes& volumes);

/// Mass correction (issue 13 "mass preserving"). The density factor moves extinction inside a
/// column, the displacement moves it across column faces, and the shape (detail.glsl detailShape)
/// erodes it at the visible edge, so the detailed field is multiplied by a correction c(x, y): c_J
/// over the core of model column J, blended to the neighbouring columns' across a band of
/// ±kCorrectionBand columns at each face (detail.glsl detailCorrectionBlend, a smoothstep), so that a
/// face is no step. The c_J are solved so that every footprint J with plain mass keeps it: on the
/// measured vertical rays r (MassPattern below), Σ_{r∈J} d_r·c(x_r) = P_J, with d_r the uncorrected
/// detailed mass of ray r, c(x_r) = Σ_K w_K(x_r)·c_K and P_J the footprint's plain mass — a sparse
/// linear system, solved by Gauss–Seidel sweeps with each c_J clamped to
/// [kMinCorrection, kMaxCorrection]; columns without plain mass stay at 1. The mass the shape
/// removes at the visible edge goes back into the rest of the footprint, most of it optically thick
/// and invisible. Every footprint with plain mass is corrected, also one whose plain mass is only a
/// neighbour's reconstruction ramp (the square face the shape removes): its remaining cloud,
/// between the cloudy neighbour and the eroded edge, carries the ramp's mass.
/// History: a bilinear factor between column centres (until the ninth session) couples each
/// footprint to its 8 neighbours over the whole footprint, and the diagonal neighbours of an
/// isolated thick column (footprint τ = 1/64 of the column's from the trilinear corner, of which the
/// shape leaves a sliver) need ×40 where the axis neighbours need ≈ ×1 — no bilinear field does both
/// (the axis neighbours then hit the range's floor, 20 footprints off by 30 % and more). A constant
/// c_J per column (ninth to nineteenth session) is exact and independent per column, but where an
/// anvil's edge is optically thin its steps at the faces show as straight seams (docs/detail.md
/// "Seams at column faces"). The band keeps each column's core its own and couples only a quarter
/// column either side of a face.
/// Measured by the GPU (glsl/render/detail_mass.comp) for rendering and by ExtinctionSampler for
/// the CPU twin, same pattern (kMassPattern).
struct RayMasses {
  int nx = 0, ny = 0;                   ///< model columns
  int rays_per_column = 0;              ///< rays per column and axis (2 × MassPattern::rays_per_axis)
  std::vector<double> plain, detailed;  ///< Σ β·Δz along each ray (any common unit), x fastest
  /// The index of ray (a, b) of column (i, j) in plain and detailed.
  std::size_t index(int i, int j, int a, int b) const {
    const std::size_t row = std::size_t(nx) * std::size_t(rays_per_column);
    return (std::size_t(j) * std::size_t(rays_per_column) + std::size_t(b)) * row +
           std::size_t(i) * std::size_t(rays_per_column) + std::size_t(a);
  }
  /// The footprint's plain and detailed masses (sums over its rays).
  double plainOf(int i, int j) const;
  double detailedOf(int i, int j) const;
};
/// Half-width of the band at a column face over which c blends between the two columns [columns]
/// (detail.glsl kDetailCorrectionBand).
inline constexpr double kCorrectionBand = 0.25;
/// Rays per half-column and axis, and the vertical step in layers, of the exhaustive measurement
/// (until the eleventh session: every half-column, the whole grown box).
inline constexpr int kMassRaysPerAxis = 2;
inline constexpr double kMassStepLayers = 0.25;

/// How the masses are measured (docs/detail.md "A cheaper mass measurement"). The vertical rays
/// sample the lattice g = −H + (k + ½)·step_layers (grid units, H = the filter's + the
/// displacement's reach in voxels, k = 0 … ⌈(nz + 2H)/step_layers⌉ − 1), at the centres of a
/// rays_per_axis² sub-grid of each half-column. With occupied_only, a footprint J is marched only
/// where its samples can be non-zero (massStepRanges): not at all when no voxel within the
/// filter's reach of the column holds cloud (its plain mass is 0, so c_J = 1 whatever D_J is),
/// and else only over the occupied layers of the columns within H, grown by H + 1 — the samples
/// skipped are exact zeros, so the sums, and c, are bit-identical to the exhaustive march's.
/// Muth 2026 §3.4.5: "sampling the full volume at a fine step size wastes the majority of samples
/// on empty air"; like its conservative quantization (§3.3.2), the skip never drops a non-zero.
struct MassPattern {
  int rays_per_axis = 2;     ///< per half-column and axis (4×4 per model column)
  double step_layers = 0.5;  ///< vertical step in model layers
  bool occupied_only = true;
};
/// The pattern of the correction in use and the exhaustive one. kMassPattern (occupied only, 4×4
/// rays per column, ½ layer) measured on the coarse storm: 3–5× faster than the exhaustive pattern
/// (5.7× / 4.8× fewer samples, trilinear / cubic), c within 1.9 % / 3.0 % of its c on every
/// footprint of τ ≥ 1; a 1-layer step moves c by up to 8–12 %, fewer rays by far more.
inline constexpr MassPattern kMassPattern{};
inline constexpr MassPattern kExhaustiveMassPattern{kMassRaysPerAxis, kMassStepLayers, false};
/// Steps of the vertical lattice over the grown box (see MassPattern).
int massSteps(int nz, int reach_voxels, double step_layers);
/// Per model column (nx × ny, x fastest): the step indices [x, y) a footprint's rays march; all of
/// them without occupied_only, none (x = y = 0) for a footprint that cannot hold plain mass.
/// filter_reach = reachVoxels(reconstruction), reach_voxels = H = filter_reach + the detail's.
std::vector<glm::ivec2> massStepRanges(const ExtinctionVolumes& volumes, int filter_reach, int reach_voxels,
                                       const MassPattern& pattern);
/// Samples (vertical rays × steps) a pattern takes per field (plain, detailed), for the benchmark.
double massSampleCount(const std::vector<glm::ivec2>& ranges, const MassPattern& pattern);
/// Range of the correction: the shape leaves a ramp-only diagonal footprint a sliver of its mass.
inline constexpr double kMinCorrection = 1.0 / 64.0, kMaxCorrection = 64.0;
/// c per model column (nx × ny, x fastest), as above.
std::vector<float> solveDetailCorrection(const RayMasses& masses);
/// The correction at continuous column index g (column centres at integers) from the c_J of
/// solveDetailCorrection: detail.glsl's blend (detail_field.glsl detailCorrectionAt), the nearest
/// column's c outside the grid.
double correctionAt(const std::vector<float>& c, int nx, int ny, const glm::dvec2& g);

/// detail.glsl's functions (compiled as C++ in float, as the GPU runs them).
glm::dvec3 detailDisplacement(const glm::dvec4& nd, double turbulence, const glm::dvec3& reach_m, const NoiseStats& s);
double detailDensity(const glm::dvec4& n1, const glm::dvec4& n2, const glm::dvec4& controls, double amplitude,
                     const NoiseStats& s);
glm::dvec3 detailSecondFrame(const glm::dvec3& q);
double detailModulation(const glm::dvec4& n1, const glm::dvec4& n2, double convective, const NoiseStats& s);
double detailColumnCoverage(double beta_per_m, const glm::dvec2& d_columns, double column_m);
double detailShape(double coverage, double m, double amplitude);
/// The noise statistics as the shaders' VolumeBlock carries them (u_noise_stats_ra, _gs, _c):
/// (r.mean, r.half, a.mean, a.half), (g.mean, g.half, stratiform.mean, stratiform.half),
/// (convective.mean, convective.half, 0, 0).
void packNoiseStats(const NoiseStats& s, glm::vec4& ra, glm::vec4& gs, glm::vec4& c);
/// detail.glsl's kDetailShapeDisplacement: the shape's coverage is read at x + this × d.
inline constexpr double kDetailShapeDisplacementScale = 3.0;

}  // namespace nph::volume
