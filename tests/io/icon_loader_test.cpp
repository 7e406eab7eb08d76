// ICON loader: regular lat-lon and native grids, vertical flip, times, and the two condensate
// consistency corrections of Muth 2026 §3.3.1 checked cell by cell.
#include <gtest/gtest.h>
#include <netcdf.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "icon_scene.h"
#include "io/icon_loader.h"
#include "io/model_file.h"
#include "io_test_support.h"
#include "physics/icon_corrections.h"

namespace nph::io {
namespace {

using nph::test::ScratchDir;

TEST(IconLoader, RegularGridLoadsBottomToTop) {
  ScratchDir dir("io");
  const std::string path = dir.file("icon.nc");
  datagen::IconSceneSpec spec;
  datagen::writeIconScene(spec, path);
  EXPECT_EQ(sniffFormat(path), FileFormat::IconRegular);
  const ModelFile file = openModelFile(path);
  ASSERT_EQ(file.timesteps().size(), 2u);
  EXPECT_EQ(nph::geo::isoOrEmpty(file.timesteps()[0].time_utc), "2026-03-18T12:00:00Z");
  EXPECT_EQ(nph::geo::isoOrEmpty(file.timesteps()[1].time_utc), "2026-03-18T13:00:00Z");
  const ModelTimestep ts = file.load(1);
  EXPECT_EQ(ts.model, ModelKind::Icon);
  EXPECT_EQ(ts.nx, 40);
  EXPECT_EQ(ts.ny, 36);
  EXPECT_EQ(ts.nz, 20);
  EXPECT_TRUE(ts.georef.geographic);
  EXPECT_NEAR(ts.georef.x0, 9.0, 1e-9);
  EXPECT_NEAR(ts.georef.y0, 46.0, 1e-9);
  EXPECT_NEAR(ts.georef.dx_m, 0.1, 1e-9);
  for (Hydrometeor h :
       {Hydrometeor::Cloud, Hydrometeor::Ice, Hydrometeor::Rain, Hydrometeor::Snow, Hydrometeor::Graupel}) {
    EXPECT_EQ(ts.q_kg_per_kg.count(h), 1u);
  }
  ASSERT_EQ(ts.cloud_cover_fraction.size(), ts.voxelCount());
  for (int j = 0; j < ts.ny; j += 5) {
    for (int i = 0; i < ts.nx; i += 5) {
      const std::size_t c = std::size_t(j) * std::size_t(ts.nx) + std::size_t(i);
      EXPECT_GT(ts.height_m[ts.index(i, j, 0)], ts.terrain_height_m[c]);
      EXPECT_LT(ts.height_m[ts.index(i, j, 0)] - ts.terrain_height_m[c], 100.0f);  // lowest layer is thin
      for (int k = 1; k < ts.nz; ++k) EXPECT_GT(ts.height_m[ts.index(i, j, k)], ts.height_m[ts.index(i, j, k - 1)]);
      EXPECT_GT(ts.pressure_pa[ts.index(i, j, 0)], ts.pressure_pa[ts.index(i, j, ts.nz - 1)]);
      EXPECT_GT(ts.temperature_k[ts.index(i, j, 0)], 250.0f);
    }
  }
  // The alpine ridge along the southern edge: terrain is higher in the south than in the north.
  EXPECT_GT(ts.terrain_height_m[std::size_t(4) * 40 + 20], ts.terrain_height_m[std::size_t(33) * 40 + 20] + 500.0f);
}

TEST(IconLoader, DescendingLatitudesGiveTheSameGrid) {
  ScratchDir dir("io");
  datagen::IconSceneSpec spec;
  spec.ntimes = 1;
  datagen::writeIconScene(spec, dir.file("north_up.nc"));
  spec.lat_descending = true;
  datagen::writeIconScene(spec, dir.file("north_down.nc"));
  const ModelTimestep a = loadIconTimestep(dir.file("north_up.nc"), 0);
  const ModelTimestep b = loadIconTimestep(dir.file("north_down.nc"), 0);
  EXPECT_DOUBLE_EQ(a.georef.y0, b.georef.y0);
  EXPECT_EQ(a.height_m, b.height_m);
  EXPECT_EQ(a.q_kg_per_kg.at(Hydrometeor::Cloud), b.q_kg_per_kg.at(Hydrometeor::Cloud));
  EXPECT_EQ(a.cloud_cover_fraction, b.cloud_cover_fraction);
}

TEST(IconCorrections, LoaderKeepsBothInconsistenciesAndPhysicsRemovesThemCellByCell) {
  ScratchDir dir("io");
  const std::string path = dir.file("icon.nc");
  datagen::IconSceneSpec spec;
  spec.ntimes = 1;
  const auto truth = datagen::writeIconScene(spec, path);
  ASSERT_GT(truth.clc_zero_with_condensate, 0);
  ASSERT_GT(truth.clc_without_condensate, 0);
  const ModelTimestep ts = loadIconTimestep(path, 0);
  const auto& qc = ts.q_kg_per_kg.at(Hydrometeor::Cloud);
  const auto& qi = ts.q_kg_per_kg.at(Hydrometeor::Ice);
  const physics::IconCorrections settings;  // Muth 2026 §3.3.1, both on
  std::int64_t seen_a = 0, seen_b = 0;
  for (std::size_t v = 0; v < ts.voxelCount(); ++v) {
    const double qw = double(qc[v]) + double(qi[v]);
    const double clc = ts.cloud_cover_fraction[v];
    ASSERT_GE(clc, 0.0);
    ASSERT_LE(clc, 1.0);  // percent converted to a fraction
    if (clc == 0.0 && qw > 0.0) ++seen_a;
    if (clc > 0.0 && qw == 0.0) ++seen_b;
    // End to end: generator -> loader -> physics corrections, against Muth's equations.
    const auto fixed = physics::correctIconCell(qc[v], qi[v], clc, ts.temperature_k[v], ts.pressure_pa[v], settings);
    const double clc_eff = std::max(clc, std::min(qw / 3.0e-5, 1.0));  // Muth eq. 3.1
    ASSERT_NEAR(fixed.cloud_cover, clc_eff, 1e-12) << "voxel " << v;
    const double f_ice = std::clamp(-(double(ts.temperature_k[v]) - 273.15) / 38.0, 0.0, 1.0);
    ASSERT_NEAR(fixed.cloud_kg_per_kg, std::max(double(qc[v]), 3.0e-5 * clc_eff * (1.0 - f_ice)), 1e-15)
        << "voxel " << v;
    ASSERT_NEAR(fixed.ice_kg_per_kg, std::max(double(qi[v]), 3.0e-5 * clc_eff * f_ice), 1e-15) << "voxel " << v;
    // Neither inconsistency survives.
    const double qw_fixed = fixed.cloud_kg_per_kg + fixed.ice_kg_per_kg;
    ASSERT_EQ(fixed.cloud_cover > 0.0, qw_fixed > 0.0) << "voxel " << v;
  }
  // The loader hands over exactly the cells the generator made inconsistent.
  EXPECT_EQ(seen_a, truth.clc_zero_with_condensate);
  EXPECT_EQ(seen_b, truth.clc_without_condensate);
}

TEST(IconLoader, NativeGridResamplesToNearestCell) {
  ScratchDir dir("io");
  const std::string path = dir.file("icon_native.nc");
  datagen::IconSceneSpec spec;
  spec.ntimes = 1;
  spec.native_divisions = 3 * 128;  // R3B7
  const auto truth = datagen::writeIconScene(spec, path);
  ASSERT_GT(truth.ncells, 200);
  EXPECT_EQ(sniffFormat(path), FileFormat::IconNative);
  const ModelFile file = openModelFile(path);
  ASSERT_EQ(file.timesteps().size(), 1u);
  EXPECT_EQ(nph::geo::isoOrEmpty(file.timesteps()[0].time_utc), "2026-03-18T12:00:00Z");  // "day as %Y%m%d.%f"
  const ModelTimestep ts = loadIconTimestep(path, 0);
  // About one target point per cell.
  const double points = double(ts.nx) * double(ts.ny);
  EXPECT_GT(points, 0.5 * double(truth.ncells));
  EXPECT_LT(points, 2.0 * double(truth.ncells));

  // Brute-force nearest cell for a sample of target points: the resampled temperature must be
  // that cell's temperature (read directly with NetCDF-C).
  int ncid = -1;
  test::ncCheck(nc_open(path.c_str(), NC_NOWRITE, &ncid), "open");
  std::vector<double> clon(std::size_t(truth.ncells)), clat(std::size_t(truth.ncells));
  int id = -1;
  test::ncCheck(nc_inq_varid(ncid, "clon", &id), "clon");
  test::ncCheck(nc_get_var_double(ncid, id, clon.data()), "clon");
  test::ncCheck(nc_inq_varid(ncid, "clat", &id), "clat");
  test::ncCheck(nc_get_var_double(ncid, id, clat.data()), "clat");
  std::vector<float> temp(std::size_t(truth.ncells) * std::size_t(spec.nz));
  test::ncCheck(nc_inq_varid(ncid, "temp", &id), "temp");
  test::ncCheck(nc_get_var_float(ncid, id, temp.data()), "temp");
  nc_close(ncid);
  double lat_min = 90, lat_max = -90;
  for (double v : clat) {
    lat_min = std::min(lat_min, v * 180.0 / std::numbers::pi);
    lat_max = std::max(lat_max, v * 180.0 / std::numbers::pi);
  }
  const double cos_mid = std::cos(0.5 * (lat_min + lat_max) * std::numbers::pi / 180.0);
  int checked = 0;
  for (int j = 0; j < ts.ny; j += 3) {
    for (int i = 0; i < ts.nx; i += 3) {
      const double lon = ts.georef.x0 + i * ts.georef.dx_m, lat = ts.georef.y0 + j * ts.georef.dy_m;
      std::size_t best = 0;
      double best_d = 1e300;
      for (std::size_t c = 0; c < clon.size(); ++c) {
        const double dx = (clon[c] * 180.0 / std::numbers::pi - lon) * cos_mid;
        const double dy = clat[c] * 180.0 / std::numbers::pi - lat;
        if (dx * dx + dy * dy < best_d) {
          best_d = dx * dx + dy * dy;
          best = c;
        }
      }
      // File level 0 is the model top; loader level nz-1.
      ASSERT_EQ(ts.temperature_k[ts.index(i, j, ts.nz - 1)], temp[best]) << "target " << i << "," << j;
      ++checked;
    }
  }
  EXPECT_GT(checked, 20);
}

TEST(IconTime, UnitsAreParsed) {
  EXPECT_EQ(nph::geo::isoOrEmpty(timeFromValue(36.0, "hours since 2026-03-18 12:00:00")), "2026-03-20T00:00:00Z");
  EXPECT_EQ(nph::geo::isoOrEmpty(timeFromValue(90.0, "minutes since 2026-12-31T23:00:00")), "2027-01-01T00:30:00Z");
  EXPECT_EQ(nph::geo::isoOrEmpty(timeFromValue(20260318.75, "day as %Y%m%d.%f")), "2026-03-18T18:00:00Z");
  EXPECT_EQ(nph::geo::isoOrEmpty(timeFromValue(1.0, "fortnights since 2026-01-01")), "");
}

}  // namespace
}  // namespace nph::io
