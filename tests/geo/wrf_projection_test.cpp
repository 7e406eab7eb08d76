// The loader's georeference (PROJ definition from MAP_PROJ & co., origin from CEN_LAT/CEN_LON)
// reproduces the generator's XLAT/XLONG at the four grid corners, for every MAP_PROJ written.
// The generator computes XLAT/XLONG with an equivalent but differently written PROJ definition
// (lat_0 = TRUELAT1, CF-style rotated pole), so this checks the loader rather than repeating it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geo/grid_georeference.h"
#include "io/wrf_loader.h"
#include "io_test_support.h"
#include "wrf_hurricane.h"

namespace nph::io {
namespace {

struct ProjectionCase {
  datagen::WrfProjection projection;
  const char* name;
  const char* proj_keyword;
  bool geographic;
};

void PrintTo(const ProjectionCase& c, std::ostream* os) { *os << c.name; }

class WrfProjectionTest : public ::testing::TestWithParam<ProjectionCase> {};

/// One timestep of the hurricane on four levels in `projection` (small and quick).
datagen::WrfHurricaneSpec smallSpec(datagen::WrfProjection projection) {
  datagen::WrfHurricaneSpec spec;
  spec.ntimes = 1;
  spec.nz = 4;
  spec.projection = projection;
  return spec;
}

/// Writes `spec` to `path`, loads it and checks the loader's georeference against XLAT/XLONG;
/// returns what the generator wrote.
datagen::WrfTruth checkCornersMatchXlatXlong(const ProjectionCase& c, const datagen::WrfHurricaneSpec& spec,
                                             const std::string& path) {
  const auto truth = datagen::writeWrfHurricane(spec, path);
  const ModelTimestep ts = loadWrfTimestep(path, 0);
  EXPECT_NE(ts.georef.proj_definition.find(c.proj_keyword), std::string::npos) << ts.georef.proj_definition;
  EXPECT_NE(ts.georef.proj_definition.find("+R=6370000"), std::string::npos);
  EXPECT_EQ(ts.georef.geographic, c.geographic);
  EXPECT_EQ(ts.georef.lat_deg.size(), std::size_t(ts.nx) * std::size_t(ts.ny));
  if (ts.georef.lat_deg.size() != std::size_t(ts.nx) * std::size_t(ts.ny)) return truth;

  const geo::MapProjection projection(ts.georef.proj_definition);
  constexpr double kToleranceDeg = 1e-3;
  for (const auto& [i, j] : {std::pair{0, 0}, std::pair{ts.nx - 1, 0}, std::pair{0, ts.ny - 1},
                             std::pair{ts.nx - 1, ts.ny - 1}, std::pair{ts.nx / 2, ts.ny / 3}}) {
    const auto [lon, lat] = geo::gridLonLat(projection, ts.georef, i, j);
    const std::size_t p = std::size_t(j) * std::size_t(ts.nx) + std::size_t(i);
    EXPECT_NEAR(lat, truth.lat_deg[p], kToleranceDeg) << c.name << " corner " << i << "," << j;
    EXPECT_NEAR(lon, truth.lon_deg[p], kToleranceDeg) << c.name << " corner " << i << "," << j;
    // And against XLAT/XLONG as the loader read them (float32).
    EXPECT_NEAR(lat, ts.georef.lat_deg[p], kToleranceDeg);
    EXPECT_NEAR(lon, ts.georef.lon_deg[p], kToleranceDeg);
  }
  // The domain spans what DX says: corner-to-corner distance along the south row ~ (nx-1) DX.
  const double lon0 = geo::gridLonLat(projection, ts.georef, 0, 0).lon_deg;
  const double lon1 = geo::gridLonLat(projection, ts.georef, ts.nx - 1, 0).lon_deg;
  EXPECT_NE(lon0, lon1);
  return truth;
}

TEST_P(WrfProjectionTest, CornersMatchXlatXlong) {
  const ProjectionCase& c = GetParam();
  nph::test::ScratchDir dir("io");
  checkCornersMatchXlatXlong(c, smallSpec(c.projection), dir.file(std::string("wrfout_") + c.name + ".nc"));
}

// The domain moved (nephele-gen wrf --centre; issue 14's terrain demo over the Alps): the
// projection follows the centre, the loader still reproduces XLAT/XLONG, the middle mass point is
// at CEN_LON/CEN_LAT, and a mountain placed at a lon/lat has its summit on the mass point there.
TEST_P(WrfProjectionTest, DomainCentredOverTheAlpsKeepsItsGeoreference) {
  const ProjectionCase& c = GetParam();
  nph::test::ScratchDir dir("io");
  datagen::WrfHurricaneSpec spec = smallSpec(c.projection);
  spec.nx = 41;  // odd: a mass point at the centre
  spec.ny = 37;
  spec.centre_lon_deg = 11.85;
  spec.centre_lat_deg = 47.1;
  spec.mountain = {11.0, 46.9, 3000.0, 35000.0};  // the Ötztal Alps: inside every projection's 600 km grid
  const datagen::WrfTruth truth =
      checkCornersMatchXlatXlong(c, spec, dir.file(std::string("wrfout_alps_") + c.name + ".nc"));
  const std::size_t middle = std::size_t(spec.ny / 2) * std::size_t(spec.nx) + std::size_t(spec.nx / 2);
  EXPECT_NEAR(truth.lon_deg[middle], 11.85, 1e-7) << c.name;
  EXPECT_NEAR(truth.lat_deg[middle], 47.1, 1e-7) << c.name;
  const auto summit = std::max_element(truth.terrain_m.begin(), truth.terrain_m.end()) - truth.terrain_m.begin();
  // Within a 15 km cell of the mountain's lon/lat (0.2° of longitude at 46.9° N, 0.14° of latitude).
  EXPECT_NEAR(truth.lon_deg[std::size_t(summit)], 11.0, 0.2) << c.name;
  EXPECT_NEAR(truth.lat_deg[std::size_t(summit)], 46.9, 0.14) << c.name;
  EXPECT_GT(truth.terrain_m[std::size_t(summit)], 2500.0);
}

// A centre the projection cannot serve is refused, naming what it needs.
TEST(WrfGeoreference, DomainCentreOutsideTheProjectionsRangeIsRefused) {
  nph::test::ScratchDir dir("io");
  datagen::WrfHurricaneSpec spec = smallSpec(datagen::WrfProjection::Lambert);
  spec.centre_lat_deg = 3.0;  // Lambert's true latitudes would straddle the equator
  EXPECT_THROW(
      {
        try {
          datagen::writeWrfHurricane(spec, dir.file("equator.nc"));
        } catch (const std::exception& e) {
          EXPECT_NE(std::string(e.what()).find("mercator"), std::string::npos) << e.what();
          throw;
        }
      },
      std::exception);
  spec.centre_lat_deg = 85.0;
  EXPECT_THROW(datagen::writeWrfHurricane(spec, dir.file("pole.nc")), std::exception);
}

INSTANTIATE_TEST_SUITE_P(
    MapProj, WrfProjectionTest,
    ::testing::Values(ProjectionCase{datagen::WrfProjection::Lambert, "lambert", "+proj=lcc", false},
                      ProjectionCase{datagen::WrfProjection::PolarStereographic, "polar", "+proj=stere", false},
                      ProjectionCase{datagen::WrfProjection::Mercator, "mercator", "+proj=merc", false},
                      ProjectionCase{datagen::WrfProjection::LatLon, "latlon", "+proj=longlat", true},
                      ProjectionCase{datagen::WrfProjection::RotatedLatLon, "rotated", "+proj=ob_tran", true}),
    [](const ::testing::TestParamInfo<ProjectionCase>& param_info) { return std::string(param_info.param.name); });

TEST(WrfGeoreference, MercatorSpacingMatchesClosedForm) {
  // Mercator true at TRUELAT1 on a sphere: x = R cos(lat_ts) (lon - lon_0) in radians, so two
  // points DX apart in x differ in longitude by DX / (R cos(lat_ts)) radians.
  WrfProjectionAttributes a;
  a.map_proj = 3;
  a.truelat1 = 30.0;
  a.stand_lon = 10.0;
  a.cen_lat = 40.0;
  a.cen_lon = 12.0;
  a.moad_cen_lat = 40.0;
  a.dx_m = 10000.0;
  a.dy_m = 10000.0;
  const geo::GridGeoreference g = wrfGeoreference(a, 101, 51, "test");
  const geo::MapProjection p(g.proj_definition);
  const auto [lon_a, lat_a] = geo::gridLonLat(p, g, 50, 25);
  const double lon_b = geo::gridLonLat(p, g, 51, 25).lon_deg;
  EXPECT_NEAR(lon_a, 12.0, 1e-9);  // the centre point is at CEN_LON/CEN_LAT
  EXPECT_NEAR(lat_a, 40.0, 1e-9);
  const double expected_dlon_deg =
      10000.0 / (kWrfEarthRadius_m * std::cos(30.0 * std::numbers::pi / 180.0)) * 180.0 / std::numbers::pi;
  EXPECT_NEAR(lon_b - lon_a, expected_dlon_deg, 1e-9);
}

}  // namespace
}  // namespace nph::io
