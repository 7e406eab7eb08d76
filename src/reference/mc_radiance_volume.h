#pragma once
// A Monte Carlo radiance volume of scattered sunlight (issue 12, item 1, "your own": the fifteenth
// session's CPU candidate for the sideways transport the independent column cannot see).
//
// Nes 2008 §5.2.3 names what the deep light map lacks: the light scattered out of the forward cone,
// in every direction, any number of times. The two_stream term (lighting/cloud_light.h) supplies it
// per independent column; the tenth session's diffusion volume (lighting/diffusion_volume.h) let it
// move sideways but is wrong where the diffusion limit fails (thin edges, clear air). This volume is
// exact in the limit instead: photons from the sun are traced through the full-resolution medium
// exactly as the path tracer traces its paths (reference/path_tracer.h: the same field and
// majorants, delta tracking with β scaled by VolumeFrame::opticalDepthScale — the exaggeration
// keeps the data's optical depth —, the phase per phase sampled exactly, albedo 1, unbiased
// Russian roulette past a depth), and the light that has scattered at least `min_order` times is
// tallied on a coarse grid by the track-length estimator (Spanier & Gelbard 1969 §3; PBRT 4th ed.
// §14.3; Novák et al. 2018 §3 "Monte Carlo methods for volumetric light transport simulation"):
// a photon of power P crossing a cell of volume V over a length ℓ in the direction d adds
// P·ℓ·Y_lm(d)/V to the cell's moments c_lm = ∫ L(ω) Y_lm(ω) dω (real spherical harmonics up to
// the spec's l ≤ 8: c_00·√(4π) is the fluence φ, (c_11, c_1−1, c_10)·√(4π/3) the flux vector F).
// Everything is in the world frame: the photons fly straight in world metres, so radiance, cell
// volumes and directions are the world's, and the eye's phase acts on world directions as in the
// path tracer.
//
// Units: per unit solar irradiance E = 1 on a plane normal to the beam. Photons start on the faces
// of the field's support box that face the sun, each face chosen with its projected area, so the
// power per photon is A_proj/N.
//
// The eye sample at x scattering towards ω (world, unit) sees the source function
// J(x, ω) = ∫ p(ω'·ω) L(x, ω') dω' = Σ_l G_l Σ_m c_lm Y_lm(ω) (Funk–Hecke; the Legendre moments of
// Henyey–Greenstein are g^l), with G_l = w·g_ice^l + (1 − w)·g_water^l for the sample's ice weight
// w (the eye pass's phase mix). Truncated at l = 0 this is φ/(4π), at l = 1 (φ + 3g·F·ω)/(4π) (the
// tenth session's convention); higher l keep more of the forward peak (G_l falls only as g^l, so
// the series converges slowly for forward-peaked light). Clamped at 0.
//
// Determinism: photon i draws from PathRng(seed, i); photons are split into a fixed number of
// chunks summed in order, so a volume is bit-identical for any thread count.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "physics/phase.h"
#include "volume/extinction_volumes.h"
#include "volume/reconstruction.h"
#include "volume/volume_frame.h"

namespace nph::reference {

inline constexpr int kMcMaxL = 8;
inline constexpr int kMcHarmonics = (kMcMaxL + 1) * (kMcMaxL + 1);  ///< real spherical harmonics up to l = 8
using McMoments = std::array<double, kMcHarmonics>;  ///< c_lm at index l² + l + m (zero past a tally's max_l)
constexpr int harmonicsUpTo(int max_l) { return (max_l + 1) * (max_l + 1); }

/// One tally: its grid and which light it keeps.
struct McTallySpec {
  int coarsen_xy = 4;     ///< fine voxels per cell horizontally (¼ of the extinction grid)
  int coarsen_z = 2;      ///< and vertically
  int min_order = 1;      ///< tally light scattered at least this many times (0: the direct beam too)
  int max_order = -1;     ///< and at most this many (−1: no limit)
  int photon_stride = 1;  ///< only photons whose index is a multiple of this (fewer photons, same trace)
  int max_l = 4;          ///< highest harmonic degree tallied (0 … kMcMaxL)
  /// Cells per coarse layer vertically (> 1: finer than the voxels, for a skin thinner than a voxel).
  int subdivide_z = 1;
};

struct McSettings {
  std::uint64_t photons = 1 << 16;
  std::uint64_t seed = 15;           ///< not the path tracer's 1: its pixel streams are PathRng(1, pixel)
  int roulette_after_events = 1000;  ///< as the path tracer (n-th collision survives n/(n + 1), weight ÷ it)
  int max_events = 100000;
  physics::PhaseMix phase;  ///< the path tracer's (HG 0.75 ice / 0.85 water by default)
  volume::Reconstruction reconstruction = volume::Reconstruction::Trilinear;
  int threads = 0;  ///< 0: TBB's default
};

struct McStats {
  std::uint64_t photons = 0;
  std::uint64_t collided = 0;  ///< photons that scattered at least once
  std::uint64_t collisions = 0;
  std::uint64_t rouletted = 0;
  std::uint64_t truncated = 0;  ///< cut by max_events (biased)
  /// Energy of scattered light leaving through the support box's top face / energy in (photons
  /// past every tally's max_order are dropped, so only meaningful when one tally has none).
  double escaped_up = 0.0;
  double seconds = 0.0;
};

/// A tallied volume (one spec).
struct McRadianceVolume {
  McTallySpec spec;
  volume::VolumeFrame frame;  ///< the fine grid's world frame
  glm::ivec3 cells{0};
  glm::dvec3 cell_m{0.0};       ///< world metres
  std::vector<double> moments;  ///< harmonicsUpTo(spec.max_l) per cell, cell-major

  int harmonics() const { return harmonicsUpTo(spec.max_l); }
  double moment(std::size_t cell, int k) const { return moments[cell * std::size_t(harmonics()) + std::size_t(k)]; }
  std::size_t index(int i, int j, int k) const {
    return (std::size_t(k) * std::size_t(cells.y) + std::size_t(j)) * std::size_t(cells.x) + std::size_t(i);
  }
  /// c_lm at a world point: trilinear between cell centres, clamped to the edge cells.
  McMoments momentsAt(const glm::dvec3& world_m) const;
  double fluenceAt(const glm::dvec3& world_m) const;
  /// J(x, ω) of the header [1/sr per unit E], the series truncated after `max_l` (0 … kMcMaxL).
  double radianceAt(const glm::dvec3& world_m, const glm::dvec3& to_eye_world, double ice_weight, double g_ice,
                    double g_water, int max_l) const;
  /// The same for every truncation at once: element l is radianceAt(…, max_l = l).
  std::array<double, kMcMaxL + 1> radianceByOrder(const glm::dvec3& world_m, const glm::dvec3& to_eye_world,
                                                  double ice_weight, double g_ice, double g_water) const;
};

/// A volume from moments computed elsewhere (the GPU's, render/dlm/radiance_volume.h readBackMoments:
/// harmonicsUpTo(spec.max_l) per cell, cell-major), on the grid `spec` gives `frame` (gridOf's rule:
/// ⌈voxels / coarsening⌉ cells from the box's min corner). Throws UsageError when the counts disagree.
McRadianceVolume mcRadianceVolumeOf(const volume::VolumeFrame& frame, const McTallySpec& spec,
                                    std::vector<double> moments);

/// Real spherical harmonics Y_lm up to l = kMcMaxL of a unit vector (index l² + l + m: 00, 1−1, 10,
/// 11, 2−2 …), by the associated Legendre recurrence (no Condon–Shortley phase; any consistent sign
/// per (l, m) gives the same Σ_m Y_lm(a)·Y_lm(b)). `max_l` limits the work; the rest is left 0.
McMoments sphericalHarmonics(const glm::dvec3& d, int max_l = kMcMaxL);
/// Σ_{l ≤ max_l} G_l Σ_m c_lm Y_lm(ω) (not clamped); G_0 is taken as 1.
double harmonicSourceFunction(const McMoments& c, const glm::dvec3& omega, const std::array<double, kMcMaxL + 1>& G,
                              int max_l);

/// Traces `settings.photons` photons from the sun (world direction `to_sun`, unit) and fills one
/// volume per spec. Throws UsageError for an empty spec list or bad settings, InputError for
/// NaN/negative voxels (the majorant grid's check).
std::vector<McRadianceVolume> traceMcRadianceVolumes(const ExtinctionVolumes& volumes, const volume::VolumeFrame& frame,
                                                     const glm::dvec3& to_sun, const std::vector<McTallySpec>& specs,
                                                     const McSettings& settings, McStats* stats = nullptr);

}  // namespace nph::reference
