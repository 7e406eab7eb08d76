#pragma once
// Helpers shared by the scene tests: small georeferenced volumes (scratch folders: support/scratch_dir.h).
#include <gtest/gtest.h>

#include "support/scratch_dir.h"
#include "volume/extinction_volumes.h"

namespace nph::scene::test {

/// Lambert conformal (WRF MAP_PROJ = 1 as the loader writes it): true latitudes 30/60, central
/// meridian −80, grid centred at (lon −80, lat 25), as WRF places a d01 domain at CEN_LAT/CEN_LON.
inline constexpr double kLccLat1 = 30.0, kLccLat2 = 60.0, kLccLat0 = 25.0, kLccLon0 = -80.0;

inline ExtinctionVolumes lambertVolumes(int nx = 100, int ny = 80, int nz = 10, double dx_m = 3000.0) {
  ExtinctionVolumes v;
  v.nx = nx;
  v.ny = ny;
  v.nz = nz;
  v.dz_m = 500.0;
  v.z_bottom_m = 0.0;
  v.georef.proj_definition =
      "+proj=lcc +lat_1=30 +lat_2=60 +lat_0=25 +lon_0=-80 +x_0=0 +y_0=0 +R=6370000 +units=m +no_defs";
  v.georef.dx_m = dx_m;
  v.georef.dy_m = dx_m;
  // (lon0, lat0) projects to (0, 0): the centre of the grid sits there.
  v.georef.x0 = -0.5 * double(nx - 1) * dx_m;
  v.georef.y0 = -0.5 * double(ny - 1) * dx_m;
  v.time_utc = nph::geo::UtcTime::parse("2026-09-01T12:00:00Z");
  v.ice_per_m.assign(v.voxelCount(), 0.0f);
  v.water_per_m.assign(v.voxelCount(), 0.0f);
  return v;
}

}  // namespace nph::scene::test
