#pragma once
// Vertical optical depth above and below every voxel centre, at the data's true height scale
// (issue 12, sky light). The eye pass lights each sample with the sky through the cloud above it
// and with the ground-reflected light through the cloud below it, attenuated by the two-stream
// diffuse transmittance of those columns (lighting/sky_light.h); this grid gives their optical
// depths:
//   τ_up(i, j, k)   = ½·β(i, j, k)·dz + Σ_{k' > k} β(i, j, k')·dz
//   τ_down(i, j, k) = ½·β(i, j, k)·dz + Σ_{k' < k} β(i, j, k')·dz
// with β = β_ice + β_water and dz the data's layer thickness (not exaggerated: height
// exaggeration keeps the data's vertical optical depth, docs/rendering.md "Conventions").
// Sampled like the extinction volumes — by the same reconstruction filter (volume/reconstruction.h:
// trilinear or the cubic B-spline between voxel centres) — but clamped to the edge (outside the
// grid the nearest column's depths hold; above the top τ_up → its value at the top centre, which
// is ½β·dz, small). The filter must match the extinction's: trilinear depths under a cubic field
// bring the grid back into the sky light and the two-stream term (issue 12/13: the power at the
// column spacing of the coarse storm went from 2.2 to 14.1 with two_stream).
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "volume/extinction_slices.h"
#include "volume/extinction_volumes.h"
#include "volume/reconstruction.h"
#include "volume/volume_frame.h"

namespace nph {

// Stored as τ_up and the column's total T = τ_up + τ_down (issue 19, memory): τ_down is T − τ_up,
// formed after filtering (both filters' weights along the column sum to 1 and T is constant along
// it, so filtering T − τ_up and subtracting the filtered values agree). The compact upload then
// keeps 2 bytes per voxel (R16F τ_up) and T per column instead of 4 (τ_up, τ_down); the two-stream
// and sky terms read τ_down only beside the total (cloud_light.glsl: k·τ_down over 4/3 + k·T), so
// its absolute error, ≤ T·2⁻¹¹ from τ_up's half, is ≤ 2⁻¹¹ of what it is compared with.

/// Depths rounded to half precision, the GPU texture's storage (τ_up and T as halves), so that
/// the CPU twin samples the values the eye pass does.
struct ColumnDepths {
  int nx = 0, ny = 0, nz = 0;
  std::vector<float> up;    ///< τ_up per voxel, ExtinctionVolumes::index layout
  std::vector<float> down;  ///< τ_down = T − τ_up per voxel, in float from the two halves
  /// The filter columnDepthAt applies: the extinction's (the eye pass's RECONSTRUCTION_CUBIC).
  volume::Reconstruction reconstruction = volume::Reconstruction::Trilinear;
};

/// The vertical optical depths of `volumes` (O(voxels), one pass per column), to be sampled with
/// `reconstruction`.
ColumnDepths columnDepths(const ExtinctionVolumes& volumes,
                          volume::Reconstruction reconstruction = volume::Reconstruction::Trilinear);

/// The column depths slice by slice from the bottom (k = 0 up to nz − 1), for an upload that never
/// holds them for the whole grid (render/dlm/volume_textures.cpp, issue 19's memory): per column
/// τ_up = (T − B) − ½β·dz in double, B the sum below the voxel, T the column's total, then τ_up
/// and T rounded to half; columnDepthsHalf is built from it, so both agree bit for
/// bit. Holds two doubles per column. Upwards, as a `.nph` timestep decodes its layers
/// (cache::NphReader::readSlices streams the chunk's zstd frame from its first layer).
class ColumnDepthSlices {
 public:
  explicit ColumnDepthSlices(const ExtinctionVolumes& volumes);  ///< one pass for the column totals
  /// The same over a source read layer by layer (volume/extinction_slices.h; `slices` must outlive
  /// this): a `.nph` upload that never holds the float volume whole.
  explicit ColumnDepthSlices(const ExtinctionSlices& slices);
  /// The same, handing every layer of the totals' pass (k = 0 up) to `see` as well: one pass that
  /// also checks the voxels (the packed upload; a `.nph` source decodes its chunk once per pass).
  ColumnDepthSlices(const ExtinctionSlices& slices,
                    const std::function<void(int k, const ExtinctionSlices::Slice& layer)>& see);
  /// Slice k's (τ_up, T) half bits, interleaved, x fastest (2·nx·ny values; T the column's
  /// total, the same in every slice): call for
  /// k = 0, 1, …, nz − 1 in turn (UsageError otherwise).
  const std::vector<std::uint16_t>& next(int k);
  /// The β of the layer the last next(k) read (valid until the next call): the packed upload
  /// writes it beside the depths without reading the layer again.
  const ExtinctionSlices::Slice& beta() const { return beta_; }

 private:
  ColumnDepthSlices(std::unique_ptr<VolumeSlices> own, const ExtinctionSlices& slices,
                    const std::function<void(int, const ExtinctionSlices::Slice&)>& see);
  std::unique_ptr<VolumeSlices> own_;  // when constructed from ExtinctionVolumes
  const ExtinctionSlices* src_;
  double dz_m_;
  std::vector<double> total_, below_;
  std::vector<std::uint16_t> slice_;
  std::vector<float> scratch_;
  ExtinctionSlices::Slice beta_;
  int next_k_;
};

/// The same depths as half-precision bit patterns, interleaved (τ_up, T) per voxel in
/// ExtinctionVolumes::index layout: the separate RG16F texel, 4 bytes per voxel (columnDepths
/// holds 8 as floats). The upload's form (render/dlm/volume_textures.cpp); columnDepths unpacks it.
std::vector<std::uint16_t> columnDepthsHalf(const ExtinctionVolumes& volumes);

/// (τ_up, τ_down) at a world point: trilinear or cubic B-spline between voxel centres
/// (depths.reconstruction), clamped to the edge (the GPU rule of the RG texture UNIT_COLUMN_DEPTH:
/// GL_LINEAR, GL_CLAMP_TO_EDGE; clouds.comp columnDepthAt).
glm::dvec2 columnDepthAt(const ColumnDepths& depths, const volume::VolumeFrame& frame, const glm::dvec3& world_m);

}  // namespace nph
