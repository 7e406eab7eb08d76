// The .nph on-disk format did not change with geo/: a file written by the cache writer of main
// 4cc50f4 (before geo::GridGeoreference replaced cache::GridGeoreference and io::Georeference)
// reads with today's reader, georeference, times and volumes included.
//
// data/lambert_4x3x2_before_geo.nph was written once with that commit's NphWriter (a 4×3 Lambert
// grid, 2 layers, 2 timesteps, with XLAT/XLONG-style geolocation) from exactly the values the
// expectations below rebuild: lat = 25 + 0.25·(n / 4), lon = −80 + 0.5·(n mod 4); ice = 1e-3·(n + t),
// water = 2e-3·((7n + t) mod 24) [1/m].
#include <gtest/gtest.h>

#include <cstddef>
#include <string>

#include "cache/nph_cache.h"
#include "cache/quantize.h"
#include "geo/grid_georeference.h"

namespace nph::geo {
namespace {

const std::string kFixture = std::string(NEPHELE_SOURCE_DIR) + "/tests/geo/data/lambert_4x3x2_before_geo.nph";

GridGeoreference fixtureGeoreference() {
  GridGeoreference g;
  g.proj_definition = "+proj=lcc +lat_1=30 +lat_2=60 +lat_0=25 +lon_0=-80 +R=6370000 +units=m +no_defs";
  g.dx_m = 3000.0;
  g.dy_m = 2500.0;
  g.x0 = -4500.0;
  g.y0 = -2500.0;
  g.geographic = false;
  for (int n = 0; n < 12; ++n) {
    g.lat_deg.push_back(25.0f + 0.25f * float(n / 4));
    g.lon_deg.push_back(-80.0f + 0.5f * float(n % 4));
  }
  return g;
}

TEST(NphBeforeGeo, FileWrittenBeforeReadsAfter) {
  const cache::NphReader reader(kFixture);
  EXPECT_EQ(reader.formatVersion(), 1u);
  const cache::NphMetadata& m = reader.metadata();
  EXPECT_EQ(m.nx, 4);
  EXPECT_EQ(m.ny, 3);
  EXPECT_EQ(m.dz_m, 500.0);
  EXPECT_EQ(m.z_bottom_m, 0.0);
  EXPECT_EQ(m.georef, fixtureGeoreference());  // every field, geolocation arrays included
  EXPECT_EQ(m.created_by, "nephele 4cc50f4 (fixture for tests/geo)");
  ASSERT_EQ(reader.timestepCount(), 2u);
  for (std::size_t t = 0; t < 2; ++t) {
    const ExtinctionVolumes v = reader.read(t);
    EXPECT_EQ(nph::geo::isoOrEmpty(v.time_utc), t == 0 ? "2026-09-01T12:00:00Z" : "2026-09-01T13:00:00Z");
    EXPECT_EQ(v.source_file, "wrfout_d01_fixture.nc");
    EXPECT_EQ(v.source_time_index, std::int64_t(t));
    EXPECT_EQ(v.georef, fixtureGeoreference());
    ASSERT_EQ(v.nz, 2);
    ASSERT_EQ(v.voxelCount(), 24u);
    // 16-bit codes: each value within the quantisation bound, about max/131070 (quantize.h).
    const double ice_tol = cache::quantisationErrorBound(v.max_ice_per_m);
    const double water_tol = cache::quantisationErrorBound(v.max_water_per_m);
    for (std::size_t n = 0; n < v.voxelCount(); ++n) {
      EXPECT_NEAR(v.ice_per_m[n], 1e-3f * float(n + t), ice_tol) << "t " << t << " voxel " << n;
      EXPECT_NEAR(v.water_per_m[n], 2e-3f * float((n * 7 + t) % 24), water_tol) << "t " << t << " voxel " << n;
    }
  }
}

}  // namespace
}  // namespace nph::geo
