// Scene georeference: world metres <-> lon/lat through PROJ, against Snyder's closed-form Lambert
// conformal conic on the sphere (Snyder 1987, "Map Projections — A Working Manual", eq. 15-1..15-5,
// 14-4), the manual offset (Nes 2008 §5.5.1), meridian convergence and the globe mapping.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "scene/georeference.h"
#include "scene/solar_position.h"
#include "scene_test_support.h"

namespace nph::scene {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct SnyderLcc {
  double n, F, rho0, R = volume::kEarthRadius_m;
  SnyderLcc() {
    const double p1 = test::kLccLat1 * kDeg, p2 = test::kLccLat2 * kDeg, p0 = test::kLccLat0 * kDeg;
    auto t = [](double p) { return std::tan(std::numbers::pi / 4.0 + p / 2.0); };
    n = std::log(std::cos(p1) / std::cos(p2)) / std::log(t(p2) / t(p1));
    F = std::cos(p1) * std::pow(t(p1), n) / n;
    rho0 = R * F / std::pow(t(p0), n);
  }
  LonLat inverse(double x, double y) const {
    const double rho = std::hypot(x, rho0 - y);
    const double theta = std::atan2(x, rho0 - y);
    return {test::kLccLon0 + theta / n / kDeg,
            (2.0 * std::atan(std::pow(R * F / rho, 1.0 / n)) - std::numbers::pi / 2.0) / kDeg};
  }
};

TEST(SceneGeoreference, LambertCornersMatchSnyder) {
  const auto v = test::lambertVolumes();
  const volume::VolumeFrame frame = volume::frameOf(v);
  const SceneGeoreference geo(v, frame);
  const SnyderLcc snyder;
  const auto corners = geo.footprintCorners();
  const double xs[4] = {v.georef.x0 - 1500.0, v.georef.x0 + 99.5 * 3000.0, v.georef.x0 + 99.5 * 3000.0,
                        v.georef.x0 - 1500.0};
  const double ys[4] = {v.georef.y0 - 1500.0, v.georef.y0 - 1500.0, v.georef.y0 + 79.5 * 3000.0,
                        v.georef.y0 + 79.5 * 3000.0};
  for (int c = 0; c < 4; ++c) {
    const LonLat expected = snyder.inverse(xs[c], ys[c]);
    EXPECT_NEAR(corners[std::size_t(c)].lon_deg, expected.lon_deg, 1e-7) << "corner " << c;
    EXPECT_NEAR(corners[std::size_t(c)].lat_deg, expected.lat_deg, 1e-7) << "corner " << c;
  }
  // The domain is centred on (lon0, lat0) and about 300 km × 240 km: corners a degree or so away.
  const LonLat centre = geo.footprintCentre();
  EXPECT_NEAR(centre.lon_deg, -80.0, 1e-9);
  EXPECT_NEAR(centre.lat_deg, 25.0, 1e-9);
  EXPECT_LT(corners[0].lon_deg, -81.0);
  EXPECT_LT(corners[0].lat_deg, 24.0);
  EXPECT_GT(corners[2].lon_deg, -79.0);
  LonLat lo, hi;
  geo.footprintBounds(lo, hi);
  EXPECT_LE(lo.lat_deg, corners[0].lat_deg);
  EXPECT_GE(hi.lat_deg, corners[2].lat_deg);
}

TEST(SceneGeoreference, RoundTripAndVoxelCentres) {
  const auto v = test::lambertVolumes();
  const volume::VolumeFrame frame = volume::frameOf(v, 10.0);
  const SceneGeoreference geo(v, frame);
  for (glm::dvec2 w :
       {glm::dvec2{0, 0}, glm::dvec2{12345.6, 200000.0}, glm::dvec2{3e5, 2.4e5}, glm::dvec2{-50000.0, 400000.0}}) {
    const glm::dvec2 back = geo.worldFromLonLat(geo.lonLatFromWorld(w));
    EXPECT_NEAR(back.x, w.x, 1e-6);
    EXPECT_NEAR(back.y, w.y, 1e-6);
  }
  // Voxel (i, j) centre in world = mass point (i, j) in projected coordinates.
  const SnyderLcc snyder;
  const int i = 17, j = 63;
  const glm::dvec3 w = frame.worldFromGrid({i + 0.5, j + 0.5, 0.5});
  const LonLat ll = geo.lonLatFromWorld({w.x, w.y});
  const LonLat expected = snyder.inverse(v.georef.x0 + i * 3000.0, v.georef.y0 + j * 3000.0);
  EXPECT_NEAR(ll.lon_deg, expected.lon_deg, 1e-7);
  EXPECT_NEAR(ll.lat_deg, expected.lat_deg, 1e-7);
  // Batch = single.
  double xy[4] = {w.x, w.y, 0.0, 0.0};
  geo.lonLatFromWorldBatch(xy, 2);
  EXPECT_NEAR(xy[0], ll.lon_deg, 1e-12);
  EXPECT_NEAR(xy[1], ll.lat_deg, 1e-12);
  EXPECT_NEAR(xy[2], geo.footprintCorners()[0].lon_deg, 1e-12);
}

TEST(SceneGeoreference, ManualOffsetShiftsLonLat) {
  const auto v = test::lambertVolumes();
  const volume::VolumeFrame frame = volume::frameOf(v);
  const SceneGeoreference plain(v, frame);
  const SceneGeoreference shifted(v, frame, LonLatOffset{0.5, -0.25});
  const LonLat c = shifted.footprintCentre();
  EXPECT_NEAR(c.lon_deg, -79.5, 1e-9);
  EXPECT_NEAR(c.lat_deg, 24.75, 1e-9);
  // lon/lat -> world undoes the offset: the shown position of a data point maps back to it.
  const glm::dvec2 w{40000.0, 70000.0};
  const glm::dvec2 back = shifted.worldFromLonLat(shifted.lonLatFromWorld(w));
  EXPECT_NEAR(back.x, w.x, 1e-6);
  EXPECT_NEAR(back.y, w.y, 1e-6);
  EXPECT_NEAR(shifted.lonLatFromWorld(w).lon_deg - plain.lonLatFromWorld(w).lon_deg, 0.5, 1e-9);
}

TEST(SceneGeoreference, MeridianConvergenceTurnsTheSun) {
  const auto v = test::lambertVolumes(400, 100, 4, 3000.0);  // 1200 km wide
  const volume::VolumeFrame frame = volume::frameOf(v);
  const SceneGeoreference geo(v, frame);
  const SnyderLcc snyder;
  // East of the central meridian, meridians lean west going north (they meet at the pole):
  // true north is n·Δλ anticlockwise of grid north.
  const glm::dvec2 east{frame.size_m().x * 0.95, frame.size_m().y * 0.5};
  const LonLat ll = geo.lonLatFromWorld(east);
  const double expected = -snyder.n * (ll.lon_deg - test::kLccLon0);
  EXPECT_LT(expected, -2.0);
  EXPECT_NEAR(geo.trueNorthClockwiseFromGridNorth_deg(east), expected, 1e-4);
  EXPECT_NEAR(geo.trueNorthClockwiseFromGridNorth_deg({frame.size_m().x * 0.5, 0.0}), 0.0, 1e-6);
  Sun noonSun;
  noonSun.azimuth_deg = 180.0;
  noonSun.elevation_deg = 60.0;
  const Sun inWorld = geo.sunInWorld(noonSun, east);
  EXPECT_NEAR(inWorld.azimuth_deg, 180.0 + expected, 1e-4);
  EXPECT_EQ(inWorld.elevation_deg, 60.0);
}

TEST(SceneGeoreference, MercatorHasGridNorthEqualTrueNorth) {
  auto v = test::lambertVolumes();
  v.georef.proj_definition = "+proj=merc +lat_ts=20 +lon_0=-60 +x_0=0 +y_0=0 +R=6370000 +units=m +no_defs";
  v.georef.x0 = 0.0;
  v.georef.y0 = 2.0e6;
  const SceneGeoreference geo(v, volume::frameOf(v));
  EXPECT_NEAR(geo.trueNorthClockwiseFromGridNorth_deg({1e5, 1e5}), 0.0, 1e-6);
  // Mercator on the sphere: x = R·k0·(λ − λ0), k0 = cos(lat_ts).
  const LonLat sw = geo.footprintCorners()[0];
  EXPECT_NEAR(sw.lon_deg, -60.0 + (-1500.0) / (volume::kEarthRadius_m * std::cos(20.0 * kDeg)) / kDeg, 1e-9);
}

TEST(SceneGeoreference, GeographicGridUsesFrameScaling) {
  ExtinctionVolumes v;
  v.nx = 50;
  v.ny = 40;
  v.nz = 5;
  v.dz_m = 200.0;
  v.georef.proj_definition = "+proj=longlat +R=6371229 +no_defs";
  v.georef.geographic = true;
  v.georef.dx_m = 0.02;
  v.georef.dy_m = 0.02;
  v.georef.x0 = 5.0;
  v.georef.y0 = 45.0;
  const volume::VolumeFrame frame = volume::frameOf(v);
  const SceneGeoreference geo(v, frame);
  for (auto [i, j] : {std::pair{0, 0}, std::pair{49, 39}, std::pair{10, 30}}) {
    const glm::dvec3 w = frame.worldFromGrid({i + 0.5, j + 0.5, 0.5});
    const LonLat ll = geo.lonLatFromWorld({w.x, w.y});
    EXPECT_NEAR(ll.lon_deg, 5.0 + 0.02 * i, 1e-9);
    EXPECT_NEAR(ll.lat_deg, 45.0 + 0.02 * j, 1e-9);
  }
}

TEST(SceneGeoreference, CartesianGridNeedsACentre) {
  ExtinctionVolumes v;
  v.nx = v.ny = 20;
  v.nz = 2;
  v.dz_m = 100.0;
  v.georef.dx_m = v.georef.dy_m = 1000.0;
  const volume::VolumeFrame frame = volume::frameOf(v);
  EXPECT_THROW(SceneGeoreference(v, frame), InputError);
  const SceneGeoreference geo(v, frame, {}, LonLat{10.0, 50.0});
  EXPECT_NEAR(geo.footprintCentre().lon_deg, 10.0, 1e-9);
  EXPECT_NEAR(geo.footprintCentre().lat_deg, 50.0, 1e-9);
  // 10 km north of the centre is 10 km / (R·π/180) degrees of latitude (azimuthal equidistant).
  EXPECT_NEAR(geo.lonLatFromWorld({10000.0, 20000.0}).lat_deg, 50.0 + 10000.0 / (volume::kEarthRadius_m * kDeg), 1e-9);
}

TEST(SceneGeoreference, BadProjectionIsAnInputError) {
  auto v = test::lambertVolumes();
  v.georef.proj_definition = "+proj=nonsense +R=6370000";
  try {
    SceneGeoreference geo(v, volume::frameOf(v));
    FAIL() << "accepted a bad projection";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("+proj=nonsense"), std::string::npos) << e.what();
  }
}

TEST(Globe, EcefMapping) {
  const double R = volume::kEarthRadius_m;
  auto near3 = [](glm::dvec3 a, glm::dvec3 b) { return glm::length(a - b) < 1e-6; };
  EXPECT_TRUE(near3(ecefFromLonLat({0, 0}), {R, 0, 0}));
  EXPECT_TRUE(near3(ecefFromLonLat({90, 0}), {0, R, 0}));
  EXPECT_TRUE(near3(ecefFromLonLat({123, 90}), {0, 0, R}));
  EXPECT_TRUE(near3(ecefFromLonLat({180, 0}, 1000.0), {-(R + 1000.0), 0, 0}));
  const LonLat back = lonLatFromEcef(ecefFromLonLat({-80.25, 25.5}, 12000.0));
  EXPECT_NEAR(back.lon_deg, -80.25, 1e-12);
  EXPECT_NEAR(back.lat_deg, 25.5, 1e-12);
  // ENU: up is the radial direction, east × north = up, north points to the pole from the equator.
  const glm::dmat3 enu = ecefFromEnu({-80.25, 25.5});
  EXPECT_TRUE(near3(enu[2] * R, ecefFromLonLat({-80.25, 25.5})));
  EXPECT_NEAR(glm::length(glm::cross(enu[0], enu[1]) - enu[2]), 0.0, 1e-12);
  EXPECT_TRUE(near3(ecefFromEnu({0, 0})[1], {0, 0, 1}));
  // World point of a georeferenced volume lands on the sphere at its height.
  const auto v = test::lambertVolumes();
  const SceneGeoreference geo(v, volume::frameOf(v));
  const glm::dvec3 p = geo.ecefFromWorld({0.5 * 300000.0, 0.5 * 240000.0, 5000.0});
  EXPECT_NEAR(glm::length(p), R + 5000.0, 1e-6);
  EXPECT_TRUE(glm::length(p - ecefFromLonLat({-80.0, 25.0}, 5000.0)) < 1e-3);
  EXPECT_DOUBLE_EQ(normaliseLongitude_deg(190.0), -170.0);
  EXPECT_DOUBLE_EQ(normaliseLongitude_deg(-180.0), 180.0);
}

}  // namespace
}  // namespace nph::scene

namespace nph::scene {
namespace {

TEST(Globe, FlatCameraCarriedOntoTheSphere) {
  const auto v = test::lambertVolumes();
  const volume::VolumeFrame frame = volume::frameOf(v, 10.0);
  const SceneGeoreference geo(v, frame);
  Camera flat;
  flat.target_m = {150000.0, 120000.0, 0.0};
  flat.position_m = {150000.0, -80000.0, 200000.0};
  const Camera g = globeCameraFrom(flat, geo);
  EXPECT_NEAR(glm::length(g.target_m), volume::kEarthRadius_m, 1e-3);
  EXPECT_NEAR(glm::length(g.position_m), volume::kEarthRadius_m + 200000.0, 1e-3);
  // Over 280 km the sphere bends the straight flat-map distance by well under 1 %.
  const double dFlat = glm::length(flat.position_m - flat.target_m), dGlobe = glm::length(g.position_m - g.target_m);
  EXPECT_NEAR(dGlobe / dFlat, 1.0, 0.01);
  // Up at the target is the local vertical; the camera is south of the target (lower latitude).
  const LonLat target = lonLatFromEcef(g.target_m), camera = lonLatFromEcef(g.position_m);
  EXPECT_NEAR(glm::dot(g.up, ecefFromEnu(target)[2]), 1.0, 1e-9);
  EXPECT_LT(camera.lat_deg, target.lat_deg);
  EXPECT_GT(g.far_m, glm::length(g.position_m));
}

TEST(Globe, SunDirectionAgreesWithTheLocalSolarPosition) {
  const UtcTime t = UtcTime::parse("2026-09-01T17:00:00Z");
  const glm::dvec3 sun = sunDirectionEcef(t);
  for (LonLat at : {LonLat{-80.0, 25.0}, LonLat{10.0, 53.5}, LonLat{150.0, -33.9}}) {
    const glm::dmat3 enu = ecefFromEnu(at);
    const glm::dvec3 local = glm::transpose(enu) * sun;  // (east, north, up)
    const SolarPosition p = solarPosition(t, at.lon_deg, at.lat_deg);
    EXPECT_NEAR(glm::degrees(std::asin(local.z)), p.elevation_deg, 1e-6);
    if (p.elevation_deg > -80.0) {
      double az = glm::degrees(std::atan2(local.x, local.y));
      az += az < 0.0 ? 360.0 : 0.0;
      EXPECT_NEAR(az, p.azimuth_deg, 1e-6);
    }
  }
  // A world-frame sun from sunInWorld maps back to the same ECEF direction (convergence undone).
  const auto v = test::lambertVolumes(400, 100, 4, 3000.0);
  const SceneGeoreference geo(v, volume::frameOf(v));
  const glm::dvec2 east{1.1e6, 1.5e5};
  const LonLat ll = geo.lonLatFromWorld(east);
  const Sun worldSun = geo.sunInWorld(sunAt(t, ll.lon_deg, ll.lat_deg), east);
  EXPECT_NEAR(glm::length(toSunEcef(worldSun, geo, east) - sun), 0.0, 1e-6);
}

}  // namespace
}  // namespace nph::scene
