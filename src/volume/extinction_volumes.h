#pragma once
// The product of the optics stage and the content of one timestep of a `.nph` cache file:
// ice and water extinction coefficients [1/m] on a uniform metric grid (Nes 2008 §5.6:
// "only two volumes are needed for every time step", one per scattering phase function).
//
// Grid: the model's native horizontal grid (nx, ny mass points, georeferenced below) and a
// uniform vertical grid of nz layers of thickness dz_m starting at z_bottom_m above mean sea
// level. Voxel (i, j, k) is centred at height z_bottom_m + (k + 0.5) * dz_m.
// Layout of both arrays: x fastest, then y, then k (bottom to top):
//   index(i, j, k) = (k * ny + j) * nx + i.
// This module does not depend on io/: both share the georeference type of geo/.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "geo/grid_georeference.h"
#include "geo/utc_time.h"

namespace nph {

/// Ice and water extinction volumes of one timestep.
struct ExtinctionVolumes {
  int nx = 0, ny = 0, nz = 0;
  double dz_m = 0.0;        ///< layer thickness
  double z_bottom_m = 0.0;  ///< height of the bottom face of layer 0 above mean sea level
  geo::GridGeoreference georef;
  geo::OptionalUtcTime time_utc;  ///< none when the data does not say
  std::string source_file;        ///< model file this timestep came from (provenance)
  std::int64_t source_time_index = 0;

  /// Ground elevation above mean sea level [m] at the nx×ny mass points (x fastest, as a layer of
  /// the volumes): the model's own field (WRF HGT, ICON HSURF / the lowest z_ifc; io/model_fields.h).
  /// Static in time, so the .nph file stores it once (cache/nph_cache.h). Empty: the ground is at
  /// sea level everywhere (generated scenes, files without terrain, .nph files before issue 14).
  std::vector<float> terrain_height_m;
  std::vector<float> ice_per_m;    ///< β_ext of ice + snow + graupel + hail [1/m]
  std::vector<float> water_per_m;  ///< β_ext of cloud + rain [1/m]
  float max_ice_per_m = 0.0f;
  float max_water_per_m = 0.0f;

  /// Model fields that steer the procedural sub-grid detail (issue 13; volume/detail.h), resampled
  /// to this grid (same layout as the extinctions), each EMPTY when the source has none: then the
  /// detail uses the documented proxies of volume/detail.h. Carried from model files
  /// (physics/volume_builder.h) and blended between timesteps; a .nph cache stores only U, V (for
  /// the motion blend, cache/nph_cache.h), so cached data uses the proxies for TKE, CLDFRA and W.
  std::vector<float> tke_m2_per_s2;   ///< turbulent kinetic energy (WRF TKE_PBL or QKE/2)
  std::vector<float> cloud_fraction;  ///< WRF CLDFRA, ICON clc/100, in [0, 1]
  std::vector<float> wind_w_m_per_s;  ///< vertical wind
  /// Horizontal wind along the grid's x and y axes (WRF U, V: grid-relative, the world frame's x and
  /// y): the detail's noise is advected with it between timesteps (volume/detail.h DetailFlow).
  std::vector<float> wind_u_m_per_s, wind_v_m_per_s;
  /// Model time of this (possibly blended) volume in seconds since kDetailClockEpoch
  /// (volume/detail.h), the clock the noise is advected by: set from time_utc by the builder, the
  /// blend of both timesteps' clocks by engine::blendVolumes; 0 without a time.
  double detail_clock_s = 0.0;

  std::size_t voxelCount() const { return std::size_t(nx) * std::size_t(ny) * std::size_t(nz); }
  std::size_t index(int i, int j, int k) const {
    return (std::size_t(k) * std::size_t(ny) + std::size_t(j)) * std::size_t(nx) + std::size_t(i);
  }
  /// Height of the centre of layer k above mean sea level [m].
  double layerCentreHeight_m(int k) const { return z_bottom_m + (double(k) + 0.5) * dz_m; }
  /// Recomputes max_ice_per_m / max_water_per_m from the arrays.
  void updateMaxima();
  /// An all-zero (clear-air) volume on a Cartesian grid of nx×ny×nz voxels, dx = dy = dx_m: the
  /// start of every built scene (tests, benchmarks, the accuracy scenes).
  static ExtinctionVolumes zeros(int nx, int ny, int nz, double dx_m, double dz_m, double z_bottom_m);
};

}  // namespace nph
