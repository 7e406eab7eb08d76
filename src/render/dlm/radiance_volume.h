#pragma once
// The Monte Carlo radiance volume on the GPU (issue 12, sixteenth session; docs/accuracy.md
// "Sixteenth session"): the fifteenth session's CPU candidate (reference/mc_radiance_volume.h, its
// twin) as two compute passes rebuilt with the deep light map (same cache rule: sun, data or
// settings changed):
//   build    glsl/dlm/radiance_volume.comp: one invocation per photon from the sun, delta tracking
//            through the eye pass's extinction against the occupancy bricks, the track-length
//            tally of the light scattered at least min_order times as real spherical harmonics
//            l ≤ 4 (25 moments) per coarse cell, fixed-point 64-bit integer sums by 32-bit atomics
//            (deterministic: the same photons give the same volume bit for bit);
//   resolve  glsl/dlm/radiance_volume_resolve.comp: the sums → c_lm = ∫ L Y_lm dω per unit
//            irradiance in seven RGBA32F 3-D textures (moment k: texture k/4, channel k mod 4),
//            GL_LINEAR between the cell centres, clamped to the edge cells.
// On a software rasteriser (llvmpipe) the same volume is traced on the CPU instead (thirty-first
// session): the twin, reference::traceMcRadianceVolumes, with the same photons, grid, orders,
// phases and roulette, its 25 moments uploaded into the same seven textures. llvmpipe runs the
// photon kernel 10-15× slower than the twin runs on the same cores (docs/accuracy.md "Thirty-first
// session"); RadianceVolumeBackend picks, Auto by the driver.
// The eye pass (multiple_scattering = radiance_volume, glsl/render/clouds.comp) reads
// J(x, ω) = Σ_l G_l Σ_m c_lm Y_lm(ω) from them (glsl/common/cloud_light.glsl
// radianceVolumeSource).
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "render/dlm/volume_textures.h"
#include "render/gl/objects.h"
#include "render/gl/program.h"

namespace nph::render {

inline constexpr int kRadianceVolumeMoments = 25;                     ///< real spherical harmonics l ≤ 4
inline constexpr int kRadianceVolumeTextures = 7;                     ///< RGBA32F textures holding them
inline constexpr std::uint32_t kRadianceVolumeMaxPhotons = 1u << 24;  ///< photons_per_column's ceiling

/// Where the photons are traced. Auto: the CPU twin on a software rasteriser (gl::softwareRasteriser)
/// when it can trace the field the eye pass reads (no sub-grid detail, not the interpolating
/// spline, whose textures hold coefficients), else the GPU.
enum class RadianceVolumeBackend { Auto, Gpu, Cpu };

struct RadianceVolumeSettings {
  std::uint32_t photons = 1u << 16;  ///< fifteenth session: 65 536 per build suffice (16 384 within 2.5 points)
  /// ... on the accuracy scenes' 24 × 24 columns of cells (114 photons a column). A larger grid
  /// gets at least this many photons per column of cells (cells.x · cells.y), at most
  /// kRadianceVolumeMaxPhotons: the demo storm's 125 × 125 columns took 65 536 photons as a
  /// mottled canopy (4 a column; thirty-first session, docs/accuracy.md). 0: `photons` alone.
  std::uint32_t photons_per_column = 64;
  std::uint32_t seed = 16;
  int coarsen_xy = 4;  ///< fine voxels per coarse cell horizontally (the CPU row's 4 × 4 × 2)
  int coarsen_z = 2;   ///< and vertically
  /// Tally the light scattered at least this many times: 2 beside the map's single scattering and
  /// forward lobe (the eye pass's convention, the CPU row "orders ≥ 2 + DLM single + forwardLobe");
  /// 1 with the exact beam; 0 with the direct beam too (tests).
  int min_order = 2;
  int roulette_after_events = 1000;  ///< as the path tracer and the CPU twin (0: never)
  int max_events = 100000;           ///< a photon is cut after this many collisions (counted)
  float g_ice = 0.75f;               ///< the Henyey–Greenstein lobes photons scatter with
  float g_water = 0.85f;
  RadianceVolumeBackend backend = RadianceVolumeBackend::Auto;
};

struct RadianceVolumeStats {
  std::uint64_t photons = 0;
  std::uint64_t collided = 0;    ///< photons that scattered at least once
  std::uint64_t collisions = 0;  ///< real collisions, all photons
  std::uint64_t rouletted = 0;
  std::uint64_t truncated = 0;  ///< cut by max_events (biased)
  std::uint64_t clamped = 0;    ///< tally additions past the fixed-point bound (clamped; expected 0)
  /// Loops that ended without their exit condition — a driver's loop limiter (llvmpipe: 65 535
  /// back-edges per SIMD group) cutting photons short; expected 0 (glsl/dlm/radiance_volume.comp).
  std::uint64_t cut_short = 0;
  int dispatches = 0;  ///< of the resumable build (photons paused after a step budget, then resumed)
  bool cpu = false;    ///< the last build traced on the CPU (RadianceVolumeBackend)
  glm::ivec3 cells{0};
  double build_ms = 0.0;  ///< both passes, wall time incl. glFinish
  bool rebuilt = false;
  std::uint64_t builds = 0, reuses = 0;
};

class RadianceVolume {
 public:
  /// `tally_every_crossing`: the sixteenth session's tally, every crossing's 25 moments added to the
  /// SSBO at once instead of once per run of crossings in one cell (the benchmark's baseline; the
  /// same sums bit for bit).
  explicit RadianceVolume(bool tally_every_crossing = false);

  /// Traces the volume for `volume` lit from `to_sun` (unit, world, towards the sun). Returns false
  /// and does nothing when the cache key (volume identity, sun, settings, backend) is unchanged.
  /// Throws UsageError for bad settings (no photons, a coarsening below 1, roulette 1, g outside
  /// (−1, 1), the CPU backend asked for a field it cannot trace).
  bool build(const VolumeTextures& volume, const glm::dvec3& to_sun, const RadianceVolumeSettings& settings);

  /// Binds the seven moment textures to units UNIT_MC_MOMENTS + 0 … 6 (render/gl/bindings.h).
  void bind() const;
  bool built() const { return bool(moments_[0]); }
  const RadianceVolumeStats& stats() const { return stats_; }
  const std::string& cacheKey() const { return key_; }
  glm::ivec3 cells() const { return stats_.cells; }
  glm::dvec3 cellSize_m() const { return cell_m_; }
  /// The fixed-point unit q of one tally addition [m] (w·ℓ·Y / q is what is summed).
  double quantum_m() const { return quantum_m_; }
  /// q·P/V: one unit of a sum in c_lm (per unit irradiance).
  double momentUnit() const { return moment_unit_; }
  /// The photons a build traces: max(photons, photons_per_column · columns), the second at most
  /// kRadianceVolumeMaxPhotons (stats().photons after a build).
  static std::uint32_t photonsFor(const glm::ivec3& cells, const RadianceVolumeSettings& settings);
  /// Whether `settings.backend` resolves to the CPU twin for `volume` on the current context.
  static bool tracesOnCpu(const VolumeTextures& volume, const RadianceVolumeSettings& settings);
  /// The 64-bit sums, 25 per cell, cell-major (x fastest): the determinism test compares them.
  /// Empty after a CPU build (it sums in double).
  std::vector<std::int64_t> readBackSums() const;
  /// The resolved moments c_lm from the textures, 25 per cell, cell-major.
  std::vector<float> readBackMoments() const;
  std::size_t textureBytes() const;

 private:
  void buildOnGpu(const VolumeTextures& volume, const glm::dvec3& sun, const RadianceVolumeSettings& s,
                  const glm::ivec3& cells);
  void buildOnCpu(const VolumeTextures& volume, const glm::dvec3& sun, const RadianceVolumeSettings& s,
                  const glm::ivec3& cells);

  gl::Program build_, resolve_;
  gl::Buffer tally_, stats_buffer_, photons_;
  gl::Texture moments_[kRadianceVolumeTextures];
  glm::dvec3 cell_m_{0.0};
  double quantum_m_ = 0.0, moment_unit_ = 0.0;
  std::string key_;
  RadianceVolumeStats stats_;
};

}  // namespace nph::render
