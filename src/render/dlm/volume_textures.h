#pragma once
// GPU copy of one timestep's ice and water extinction volumes plus its occupancy grid.
// An absent phase (all zero) gets no texture and is never fetched.
#include <memory>
#include <string>

#include "render/dlm/noise_texture.h"
#include "render/gl/objects.h"
#include "render/gl/program.h"
#include "render/gl/uniform_blocks.h"
#include "volume/detail.h"
#include "volume/extinction_slices.h"
#include "volume/extinction_volumes.h"
#include "volume/occupancy.h"
#include "volume/terrain_field.h"
#include "volume/volume_frame.h"

namespace nph::render {

/// Which copies of the volume an upload makes (issue 19, docs/benchmarks.md "Memory").
enum class VolumeStorage {
  /// The packed RGBA16F texture alone wherever it serves (trilinear, no detail): every pass reads
  /// β in half precision from it, 8 bytes per voxel. The cubic filter and the detail get the
  /// separate textures (R32F ice and water, RG16F column depths: 12 bytes per voxel).
  Compact,
  /// Both: the packed texture for the eye pass and the separate ones, from which the DLM passes
  /// (and an eye pass with EyePassBaseline::separate_textures) read β in float, as before the
  /// packed texture. The reference of tests and benchmarks; its identity gets "|reference".
  Reference,
};

/// How VolumeTextures::upload builds the textures (issue 19 item 3: one struct instead of eight
/// positional parameters). Defaults: trilinear, 8-voxel bricks, no detail, Compact, no user DEM.
struct UploadOptions {
  /// The filter every pass applies (volume/reconstruction.h): the occupancy is dilated by its
  /// reach, and a cubic upload's identity gets "|cubic" appended (a DLM built with one filter is
  /// never reused for the other).
  volume::Reconstruction reconstruction = volume::Reconstruction::Trilinear;
  int brick_voxels = 8;  ///< the occupancy's brick edge
  /// Other than None (volume/detail.h): the per-voxel controls are built and uploaded, the noise
  /// tile is `noise` or generated now (NoiseTexture::generate), the occupancy is dilated by the
  /// displacement's reach too and its maxima × 2·max c, the per-column mass correction c is
  /// measured on the GPU with `mass` and solved, and the identity gets "|detail=<name>" (and
  /// "|mass=<rays>,<step>,<occupied>" for a pattern other than kMassPattern: benchmarks, tests).
  volume::Detail detail = volume::Detail::None;
  std::shared_ptr<const NoiseTexture> noise = nullptr;
  VolumeStorage storage = VolumeStorage::Compact;
  /// A user DEM (scene/dem.h) resampled for the terrain (volume::terrainOf's rule: it wins where
  /// it has data) and its far field beyond the domain; null for none. The DLM does not read the
  /// terrain, so the identity does not change with it. Must outlive the upload call only.
  const volume::DemHeights* dem = nullptr;
  volume::MassPattern mass = volume::kMassPattern;
};

class VolumeTextures {
 public:
  /// Uploads `volumes` placed by `frame` as `options` say; `identity` names this content (file +
  /// timestep) for the DLM cache key — two uploads with the same identity must hold the same data.
  /// Throws InputError for a NaN, infinite, negative or absurd (> 1e6 /m) voxel.
  static VolumeTextures upload(const ExtinctionVolumes& volumes, const volume::VolumeFrame& frame, std::string identity,
                               const UploadOptions& options = {});
  /// The same from a source read layer by layer (volume/extinction_slices.h; issue 19, memory):
  /// where the packed texture is the only copy (trilinear, no detail, Compact) the checks, the
  /// occupancy, the column depths and the packed texture are built a layer at a time, so a
  /// cache::NphReader::readSlices source never holds its float volume whole; the other paths
  /// materialise it. The same textures, bit for bit, as upload(slices.materialise(), …).
  static VolumeTextures upload(const ExtinctionSlices& slices, const volume::VolumeFrame& frame, std::string identity,
                               const UploadOptions& options = {});

  const volume::VolumeFrame& frame() const { return frame_; }
  const volume::OccupancyGrid& occupancy() const { return occupancy_; }
  const std::string& identity() const { return identity_; }
  volume::Reconstruction reconstruction() const { return reconstruction_; }
  const volume::DetailParameters& detail() const { return detail_; }
  /// The noise tile in use (null without detail): pass it to the next upload to reuse it.
  const std::shared_ptr<const NoiseTexture>& noise() const { return noise_; }
  /// Whether the detail's noise is advected by the data's U, V (the wind texture exists).
  bool hasDetailWind() const { return bool(wind_); }
  bool hasIce() const { return has_ice_; }
  /// The packed texture of the eye pass (issue 19 item 3; glsl/render/clouds.comp packedAt): one
  /// RG16F texel per voxel holding (β_ice, β_water) in units of packedBetaUnit_per_m(), GL_LINEAR,
  /// GL_CLAMP_TO_EDGE, beside the column depth τ_up (R16F, or the separate RG16F (τ_up, T)) and
  /// the column totals T (UNIT_COLUMNS): 6 bytes per voxel.
  /// Built for the trilinear filter without sub-grid detail only (the cubic B-spline reads the zero
  /// border, the detail displaces its fetches): otherwise the separate textures serve.
  bool hasPacked() const { return bool(packed_); }
  float packedBetaUnit_per_m() const { return packed_beta_unit_per_m_; }
  /// The packed texture's texels as half bits: (β_ice, β_water) per voxel in ExtinctionVolumes::index
  /// order, then τ_up per voxel, then T per column; empty without it (tests: a layered upload
  /// against a float one).
  std::vector<std::uint16_t> readBackPacked() const;
  /// β as the passes read it, back from the GPU: the separate float textures where they exist,
  /// else the packed texture's half floats × its unit, a layer at a time; on the frame's grid
  /// (nx, ny, nz and the arrays; the geometry is frame()'s). For the CPU twin of the radiance
  /// volume (render/dlm/radiance_volume.h) where the upload kept no float copy.
  ExtinctionVolumes readBackExtinction() const;
  bool hasWater() const { return has_water_; }
  /// The separate R32F ice and water textures exist (VolumeStorage; the cubic filter, the detail).
  bool hasSeparateTextures() const { return separate_; }
  /// Bytes of the GL textures this upload allocated (gl::Texture::bytes; not the shared noise tile).
  std::size_t bytes() const;
  /// World AABB of the non-empty voxels grown by the filter's reach (1 voxel trilinear, 2 cubic);
  /// empty → the volume's bottom face.
  void nonEmptyBox(glm::dvec3& lo, glm::dvec3& hi) const;
  /// The ground's height field of this timestep (issue 14), placed by frame(); not present()
  /// when the volumes carry no terrain or only sea level.
  const volume::TerrainField& terrain() const { return terrain_; }

  /// Binds the textures to units UNIT_ICE_PER_M, UNIT_WATER_PER_M, UNIT_OCCUPANCY_PER_M and
  /// UNIT_COLUMN_DEPTH (the sky light's column optical depths, volume/column_depth.h),
  /// UNIT_DETAIL_CONTROLS, UNIT_DETAIL_NOISE (1-texel zeros without detail), UNIT_COLUMNS
  /// (per model column the detail's mass correction, 1 without detail, and the total optical depth
  /// T), UNIT_DETAIL_WIND (the wind
  /// advecting the noise, RG32F; a 1-texel zero without detail or without U, V) and the
  /// VolumeBlock of glsl/dlm/volume.glsl to UBO_VOLUME (render/gl/bindings.h), for every program,
  /// and the terrain heights (R32F, one texel per mass point, 1×1 zero without terrain) to
  /// UNIT_TERRAIN, the far terrain (a user DEM beyond the domain; 1×1 zero without) to
  /// UNIT_FAR_TERRAIN, and the packed texture (or a 1-texel zero) to UNIT_PACKED_VOLUME.
  void bind() const;

  /// The plain and the uncorrected detailed masses along the vertical rays of a detailed upload,
  /// measured on the GPU with `pattern` (glsl/render/detail_mass.comp; volume/detail.h); `volumes`
  /// are the ones uploaded (for the pattern's step ranges). Binds the textures.
  volume::RayMasses measureRayMasses(const ExtinctionVolumes& volumes, const volume::MassPattern& pattern) const;

 private:
  gl::Texture ice_, water_, occupancy_tex_, column_depth_, zero_, terrain_tex_, far_terrain_tex_, controls_, zero_rgba_,
      columns_, wind_;
  gl::Texture packed_;
  float packed_beta_unit_per_m_ = 0.0f;
  bool has_ice_ = false, has_water_ = false, separate_ = false;
  volume::TerrainField terrain_;
  std::shared_ptr<const NoiseTexture> noise_;
  volume::DetailParameters detail_;
  gl::UniformBuffer<gl::VolumeBlock> block_;
  volume::VolumeFrame frame_;
  volume::OccupancyGrid occupancy_;
  std::string identity_;
  volume::Reconstruction reconstruction_ = volume::Reconstruction::Trilinear;
};

}  // namespace nph::render
