#pragma once
// Where an extinction volume sits in world space (flat-map view).
//
// World frame (metres): x east and y north in the data's map projection, measured from the outer
// corner of grid cell (0, 0) — the volume's footprint is [0, size.x] × [0, size.y]; z is height
// above mean sea level times the height exaggeration (Nes 2008 §5.5.2). Voxel (i, j, k) is
// centred at ((i + ½)·dx, (j + ½)·dy, z_bottom + (k + ½)·dz).
// For geographic (lat-lon) grids the spacing in degrees is turned into metres on WRF's sphere at
// the grid's central latitude (a local equirectangular approximation, fine for regional domains).
#include <glm/glm.hpp>

#include "volume/extinction_volumes.h"

namespace nph::volume {

/// Sphere radius WRF and nephele's flat-map frame use [m] (WRF share/module_model_constants).
inline constexpr double kEarthRadius_m = 6370000.0;

struct VolumeFrame {
  glm::ivec3 voxels{0};          ///< nx, ny, nz
  glm::dvec3 voxel_size_m{0.0};  ///< dx, dy, dz·exaggeration in world metres
  double z_bottom_m = 0.0;       ///< world z of the bottom face of layer 0 (already exaggerated)
  double height_exaggeration = 1.0;

  glm::dvec3 size_m() const { return glm::dvec3(voxels) * voxel_size_m; }
  glm::dvec3 min_m() const { return {0.0, 0.0, z_bottom_m}; }
  glm::dvec3 max_m() const { return min_m() + size_m(); }
  /// World position -> continuous grid coordinates (voxel centres at integer + 0.5).
  glm::dvec3 gridFromWorld(const glm::dvec3& world_m) const { return (world_m - min_m()) / voxel_size_m; }
  glm::dvec3 worldFromGrid(const glm::dvec3& grid) const { return min_m() + grid * voxel_size_m; }
  /// Height exaggeration keeps the data's optical depth (issue 12; docs/rendering.md
  /// "Conventions"): a world path of length ℓ along the unit direction `dir` has the optical depth
  /// of its unexaggerated image, ℓ·|(d_x, d_y, d_z/e)|·β. This is that factor f(dir): 1 for
  /// horizontal paths, 1/e for vertical ones; every integrator multiplies β by it.
  double opticalDepthScale(const glm::dvec3& dir) const {
    const double e = height_exaggeration > 0.0 ? height_exaggeration : 1.0;
    return glm::length(glm::dvec3(dir.x, dir.y, dir.z / e)) / glm::length(dir);
  }
};

/// The frame of `volumes` with heights scaled by `height_exaggeration` (≥ 1 typical; 1 = true scale).
VolumeFrame frameOf(const ExtinctionVolumes& volumes, double height_exaggeration = 1.0);

}  // namespace nph::volume
