// geo::MapProjection, the one PROJ wrapper: against the closed-form spherical Mercator (Snyder
// 1987, "Map Projections — A Working Manual", eq. 7-1, 7-2 with k0 = cos φ_ts, and 7-4), the
// figure of the Earth taken from the definition (no datum shift), and its errors.
#include "geo/map_projection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "core/error.h"
#include "geo/grid_georeference.h"

namespace nph::geo {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kR_m = 6370000.0;  // WRF's sphere

TEST(MapProjection, SphericalMercatorMatchesSnyder) {
  const MapProjection p("+proj=merc +lat_ts=30 +lon_0=10 +x_0=0 +y_0=0 +R=6370000 +units=m +no_defs");
  const double k0 = std::cos(30.0 * kDeg);
  for (const LonLat ll : {LonLat{10.0, 0.0}, LonLat{12.5, 40.0}, LonLat{-20.0, -55.0}}) {
    const glm::dvec2 xy = p.forward(ll);
    EXPECT_NEAR(xy.x, kR_m * k0 * (ll.lon_deg - 10.0) * kDeg, 1e-6);
    EXPECT_NEAR(xy.y, kR_m * k0 * std::log(std::tan(std::numbers::pi / 4.0 + ll.lat_deg * kDeg / 2.0)), 1e-6);
    const LonLat back = p.inverse(xy);
    EXPECT_NEAR(back.lon_deg, ll.lon_deg, 1e-12);
    EXPECT_NEAR(back.lat_deg, ll.lat_deg, 1e-12);
  }
  EXPECT_EQ(p.definition(), "+proj=merc +lat_ts=30 +lon_0=10 +x_0=0 +y_0=0 +R=6370000 +units=m +no_defs");
}

TEST(MapProjection, LonLatAreOnTheDefinitionsOwnSphere) {
  // A longlat "projection" on WRF's sphere is the identity: no datum shift to WGS84 (header).
  const MapProjection sphere("+proj=longlat +R=6370000 +no_defs");
  const glm::dvec2 xy = sphere.forward({-75.0, 25.0});
  EXPECT_DOUBLE_EQ(xy.x, -75.0);
  EXPECT_DOUBLE_EQ(xy.y, 25.0);
  // A rotated pole at 90° is no rotation either.
  const MapProjection rotated("+proj=ob_tran +o_proj=longlat +o_lat_p=90 +o_lon_p=0 +lon_0=0 +R=6370000 +no_defs");
  const LonLat ll = rotated.inverse({12.0, 34.0});
  EXPECT_NEAR(ll.lon_deg, 12.0, 1e-9);
  EXPECT_NEAR(ll.lat_deg, 34.0, 1e-9);
}

TEST(MapProjection, ErrorsNameTheDefinitionAndThePoint) {
  for (const char* bad : {"", "+proj=nonsense +R=6370000"}) {
    try {
      const MapProjection p(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("projection '") + bad + "'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("+proj=lcc"), std::string::npos) << "an example: " << e.what();
    }
  }
  // Orthographic: the far side of the globe has no image, and a point beyond the disc of radius R
  // has no lon/lat.
  const MapProjection ortho("+proj=ortho +lat_0=0 +lon_0=0 +R=6370000");
  try {
    (void)ortho.forward({180.0, 0.0});
    ADD_FAILURE() << "projected the antipode";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'+proj=ortho +lat_0=0 +lon_0=0 +R=6370000' cannot project lon 180 lat 0"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW((void)ortho.inverse({2.0 * kR_m, 0.0}), InputError);
  double xy[4] = {0.0, 0.0, 2.0 * kR_m, 0.0};
  ortho.inverseBatch(xy, 2);
  EXPECT_NEAR(xy[0], 0.0, 1e-12);
  EXPECT_NEAR(xy[1], 0.0, 1e-12);
  EXPECT_TRUE(std::isnan(xy[2]) && std::isnan(xy[3]));
}

TEST(MapProjection, MovesAndLongitudesNormalise) {
  MapProjection a("+proj=merc +lon_0=0 +R=6370000");
  MapProjection b(std::move(a));
  EXPECT_NEAR(b.inverse(b.forward({45.0, 45.0})).lat_deg, 45.0, 1e-12);
  EXPECT_DOUBLE_EQ(normaliseLongitude_deg(190.0), -170.0);
  EXPECT_DOUBLE_EQ(normaliseLongitude_deg(-180.0), 180.0);
  EXPECT_DOUBLE_EQ(normaliseLongitude_deg(540.0), 180.0);
}

TEST(GridGeoreference, MassPointsThroughTheProjection) {
  // A Mercator grid whose point (2, 1) sits on lon_0 at the equator: x = x0 + i dx, y = y0 + j dy.
  GridGeoreference g;
  g.proj_definition = "+proj=merc +lon_0=10 +R=6370000";
  g.dx_m = 5000.0;
  g.dy_m = 4000.0;
  g.x0 = -10000.0;
  g.y0 = -4000.0;
  EXPECT_EQ(g.projectedAt(2.0, 1.0), glm::dvec2(0.0, 0.0));
  EXPECT_EQ(g.projectedAt(0.5, 0.0), glm::dvec2(-7500.0, -4000.0));
  const MapProjection p(g.proj_definition);
  const LonLat centre = gridLonLat(p, g, 2.0, 1.0);
  EXPECT_NEAR(centre.lon_deg, 10.0, 1e-12);
  EXPECT_NEAR(centre.lat_deg, 0.0, 1e-12);
  // One dx east on the equator is dx / R radians of longitude (k0 = 1).
  EXPECT_NEAR(gridLonLat(p, g, 3.0, 1.0).lon_deg - 10.0, 5000.0 / kR_m / kDeg, 1e-12);
  GridGeoreference h = g;
  EXPECT_EQ(h, g);
  h.lat_deg = {1.0f};
  EXPECT_NE(h, g);
}

}  // namespace
}  // namespace nph::geo
