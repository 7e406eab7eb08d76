#pragma once
// Coarse occupancy (max-extinction) grid for empty-space skipping (Nes 2008 §3.2.2; Muth 2026
// §3.4: skip empty bricks, not just empty samples). Brick (bi, bj, bk) covers voxels
// [b·B, (b+1)·B) per axis and stores the maximum of ice + water extinction over those voxels
// DILATED by the reconstruction's reach on every side (volume/reconstruction.h: 1 voxel for
// trilinear, 2 for the cubic B-spline), so a brick whose stored max is 0 returns exactly 0
// everywhere inside it. Both filters have non-negative weights summing to at most 1, so the same
// grid bounds every sample in the brick (the majorant for delta tracking).
//
// A lower bound per brick too (issue 19, the DLM's adaptive light step): min_per_m is the least
// voxel of the brick and its 26 neighbours (0 where a neighbour lies outside the grid), so with
// the trilinear filter (reach 1 ≤ brick) or the cubic B-spline (reach 2; both non-negative weights
// over voxels inside that block, the zero border outside it) every sample in the brick is at least
// that. It is 0 where no such bound holds: the interpolating spline (negative coefficients, β
// clamped at 0) and the sub-grid detail (ρ ∈ [0, 2], displacement beyond the neighbours).
#include <vector>

#include <glm/glm.hpp>

#include "volume/extinction_slices.h"
#include "volume/extinction_volumes.h"
#include "volume/reconstruction.h"

namespace nph::volume {

struct OccupancyGrid {
  int brick = 8;                                         ///< voxels per brick side
  int dilation_voxels = 1;                               ///< the reach the bricks were dilated by
  glm::ivec3 bricks{0};                                  ///< brick counts
  std::vector<float> max_per_m;                          ///< per brick, x fastest
  std::vector<float> min_per_m;                          ///< per brick: a lower bound of β in it (see above)
  glm::ivec3 nonEmptyMinVoxel{0}, nonEmptyMaxVoxel{-1};  ///< inclusive voxel bounds of β > 0
  bool empty() const { return nonEmptyMaxVoxel.x < nonEmptyMinVoxel.x; }
  float at(int i, int j, int k) const {
    return max_per_m[(std::size_t(k) * std::size_t(bricks.y) + std::size_t(j)) * std::size_t(bricks.x) +
                     std::size_t(i)];
  }
};

/// `extra_reach_voxels` grows the dilation beyond the filter's reach and `max_scale` multiplies the
/// stored maxima: the sub-grid detail (volume/detail.h) displaces samples by up to its reach and
/// multiplies β by at most kMaxDetailDensity, so a brick stays a bound of the detailed field.
OccupancyGrid buildOccupancy(const ExtinctionVolumes& volumes, int brick = 8,
                             Reconstruction reconstruction = Reconstruction::Trilinear, int extra_reach_voxels = 0,
                             float max_scale = 1.0f);
/// The same from a source read layer by layer (volume/extinction_slices.h: the upload of a `.nph`
/// timestep that never holds its floats whole); buildOccupancy(volumes) is this over VolumeSlices.
/// `slices` are the voxels the filter reads: for CubicInterpolating, the spline coefficients
/// (buildOccupancy(volumes) converts the voxels itself).
OccupancyGrid buildOccupancy(const ExtinctionSlices& slices, int brick = 8,
                             Reconstruction reconstruction = Reconstruction::Trilinear, int extra_reach_voxels = 0,
                             float max_scale = 1.0f);

/// buildOccupancy fed a layer at a time, k = 0, 1, …, nz − 1, by a pass that reads the layers for
/// something else too (the packed upload writes its texture in the same pass: a `.nph` source
/// decodes its chunk once per pass). finish() gives what buildOccupancy gives.
class OccupancyBuilder {
 public:
  /// `grid`: the volume's header (nx, ny, nz); the other arguments are buildOccupancy's.
  OccupancyBuilder(const ExtinctionVolumes& grid, int brick = 8,
                   Reconstruction reconstruction = Reconstruction::Trilinear, int extra_reach_voxels = 0,
                   float max_scale = 1.0f);
  /// Layer k (UsageError unless k is the next layer).
  void add(int k, const ExtinctionSlices::Slice& layer);
  /// The grid, once every layer is added (UsageError otherwise).
  OccupancyGrid finish();

 private:
  glm::ivec3 n_;
  Reconstruction reconstruction_;
  int extra_reach_voxels_;
  float max_scale_;
  int next_k_ = 0;
  OccupancyGrid g_;
  std::vector<float> own_min_;  // the least voxel per brick, undilated
};

}  // namespace nph::volume
