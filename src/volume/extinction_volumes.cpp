#include "volume/extinction_volumes.h"

#include <algorithm>

namespace nph {

void ExtinctionVolumes::updateMaxima() {
  max_ice_per_m = ice_per_m.empty() ? 0.0f : *std::max_element(ice_per_m.begin(), ice_per_m.end());
  max_water_per_m = water_per_m.empty() ? 0.0f : *std::max_element(water_per_m.begin(), water_per_m.end());
  max_ice_per_m = std::max(max_ice_per_m, 0.0f);
  max_water_per_m = std::max(max_water_per_m, 0.0f);
}

ExtinctionVolumes ExtinctionVolumes::zeros(int nx, int ny, int nz, double dx_m, double dz_m, double z_bottom_m) {
  ExtinctionVolumes v;
  v.nx = nx;
  v.ny = ny;
  v.nz = nz;
  v.dz_m = dz_m;
  v.z_bottom_m = z_bottom_m;
  v.georef.dx_m = dx_m;
  v.georef.dy_m = dx_m;
  v.ice_per_m.assign(v.voxelCount(), 0.0f);
  v.water_per_m.assign(v.voxelCount(), 0.0f);
  return v;
}

}  // namespace nph
