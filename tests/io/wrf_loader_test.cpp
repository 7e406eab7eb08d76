// WRF loader against the generator's truth: heights from PH/PHB, P+PB, T from θ and Exner,
// hydrometeor classes per scheme, number concentrations, times and series of files.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "io/model_file.h"
#include "io/wrf_loader.h"
#include "io_test_support.h"
#include "wrf_hurricane.h"

namespace nph::io {
namespace {

using datagen::WrfHurricaneSpec;
using nph::test::ScratchDir;

WrfHurricaneSpec smallSpec() {
  WrfHurricaneSpec s;  // tiny preset: 40 x 36 x 20
  s.ntimes = 2;
  s.keep_truth = true;
  return s;
}

double maxAbsDiff(const std::vector<float>& a, const std::vector<double>& b) {
  double worst = 0.0;
  for (std::size_t n = 0; n < a.size(); ++n) worst = std::max(worst, std::abs(double(a[n]) - b[n]));
  return worst;
}

TEST(WrfLoader, StateMatchesGeneratorTruth) {
  ScratchDir dir("io");
  const std::string path = dir.file("wrfout_d01.nc");
  const auto truth = datagen::writeWrfHurricane(smallSpec(), path);
  for (std::int64_t t = 0; t < 2; ++t) {
    const ModelTimestep ts = loadWrfTimestep(path, t);
    ASSERT_EQ(ts.nx, 40);
    ASSERT_EQ(ts.ny, 36);
    ASSERT_EQ(ts.nz, 20);
    ASSERT_EQ(ts.height_m.size(), ts.voxelCount());
    // Heights: (PH + PHB) / g on w levels, averaged to mass levels. float32 geopotential of ~2e5
    // m2/s2 carries ~0.02 m2/s2 of rounding, i.e. ~2 mm in height: 0.05 m leaves margin.
    EXPECT_LT(maxAbsDiff(ts.height_m, truth.height_m[std::size_t(t)]), 0.05);
    // P + PB: two float32 values of up to 1e5 Pa, each rounded to ~0.004 Pa.
    EXPECT_LT(maxAbsDiff(ts.pressure_pa, truth.pressure_pa[std::size_t(t)]), 0.05);
    // T from theta = T + 300 and Exner; the result is stored as float32 (~3e-5 K at 300 K).
    EXPECT_LT(maxAbsDiff(ts.temperature_k, truth.temperature_k[std::size_t(t)]), 1e-3);
  }
}

TEST(WrfLoader, AtmosphereIsPhysicallyPlausible) {
  ScratchDir dir("io");
  const std::string path = dir.file("wrfout_d01.nc");
  datagen::writeWrfHurricane(smallSpec(), path);
  const ModelTimestep ts = loadWrfTimestep(path, 0);
  for (int j = 0; j < ts.ny; j += 7) {
    for (int i = 0; i < ts.nx; i += 7) {
      const std::size_t c = ts.index(i, j, 0);
      EXPECT_GT(ts.height_m[c], ts.terrain_height_m[std::size_t(j) * std::size_t(ts.nx) + std::size_t(i)]);
      EXPECT_GT(ts.pressure_pa[c], 90000.0f);
      EXPECT_LT(ts.pressure_pa[c], 103000.0f);
      EXPECT_GT(ts.temperature_k[c], 280.0f);
      for (int k = 1; k < ts.nz; ++k) {
        EXPECT_GT(ts.height_m[ts.index(i, j, k)], ts.height_m[ts.index(i, j, k - 1)]);
        EXPECT_LT(ts.pressure_pa[ts.index(i, j, k)], ts.pressure_pa[ts.index(i, j, k - 1)]);
      }
      const std::size_t top = ts.index(i, j, ts.nz - 1);
      EXPECT_GT(ts.height_m[top], 17000.0f);     // model top at 50 hPa is ~20.6 km
      EXPECT_LT(ts.temperature_k[top], 225.0f);  // lower stratosphere
    }
  }
  // Terrain: the island peak is in HGT and equals the lowest w level.
  const float peak = *std::max_element(ts.terrain_height_m.begin(), ts.terrain_height_m.end());
  EXPECT_GT(peak, 400.0f);
  EXPECT_LT(peak, 701.0f);
}

TEST(WrfLoader, ThompsonLikeHasSeparateIceAndNumberConcentrations) {
  ScratchDir dir("io");
  const std::string path = dir.file("wrfout_d01.nc");
  auto spec = smallSpec();
  spec.include_hail = true;
  datagen::writeWrfHurricane(spec, path);
  const ModelTimestep ts = loadWrfTimestep(path, 0);
  EXPECT_EQ(ts.microphysics_scheme, 8);
  EXPECT_EQ(ts.q_kg_per_kg.size(), 6u);
  EXPECT_EQ(ts.number_per_kg.size(), 6u);
  for (Hydrometeor h : kAllHydrometeors) {
    ASSERT_EQ(ts.q_kg_per_kg.count(h), 1u);
    const auto& q = ts.q_kg_per_kg.at(h);
    EXPECT_GT(*std::max_element(q.begin(), q.end()), 1e-5f) << "class " << int(h);
    EXPECT_GE(*std::min_element(q.begin(), q.end()), 0.0f);
  }
  // Ice lives only below 0 °C.
  const auto& qi = ts.q_kg_per_kg.at(Hydrometeor::Ice);
  for (std::size_t v = 0; v < qi.size(); ++v) {
    if (qi[v] > 0.0f) {
      ASSERT_LT(ts.temperature_k[v], 273.2f);
    }
  }
  // N = q / (4/3 pi r^3 rho) with r = 10 µm +-20 % for cloud water (generator's assumption).
  const auto& qc = ts.q_kg_per_kg.at(Hydrometeor::Cloud);
  const auto& nc = ts.number_per_kg.at(Hydrometeor::Cloud);
  const std::size_t v = std::size_t(std::max_element(qc.begin(), qc.end()) - qc.begin());
  const double r = std::cbrt(double(qc[v]) / (double(nc[v]) * 4.0 / 3.0 * std::numbers::pi * 1000.0));
  EXPECT_GT(r, 7.9e-6);
  EXPECT_LT(r, 12.1e-6);
}

TEST(WrfLoader, Wsm3LikeHasOnlyCloudAndRainWithFrozenCondensate) {
  ScratchDir dir("io");
  const std::string path = dir.file("wrfout_wsm3.nc");
  auto spec = smallSpec();
  spec.scheme = datagen::WrfScheme::Wsm3Like;
  datagen::writeWrfHurricane(spec, path);
  const ModelTimestep ts = loadWrfTimestep(path, 0);
  EXPECT_EQ(ts.microphysics_scheme, 3);
  ASSERT_EQ(ts.q_kg_per_kg.size(), 2u);
  EXPECT_EQ(ts.q_kg_per_kg.count(Hydrometeor::Cloud), 1u);
  EXPECT_EQ(ts.q_kg_per_kg.count(Hydrometeor::Rain), 1u);
  EXPECT_TRUE(ts.number_per_kg.empty());
  // WSM3 keeps cloud ice in QCLOUD and snow in QRAIN below 0 °C: both hold condensate at -40 °C.
  const auto& qc = ts.q_kg_per_kg.at(Hydrometeor::Cloud);
  const auto& qr = ts.q_kg_per_kg.at(Hydrometeor::Rain);
  float cold_cloud = 0.0f, cold_rain = 0.0f;
  for (std::size_t v = 0; v < qc.size(); ++v) {
    if (ts.temperature_k[v] < 233.0f) {
      cold_cloud = std::max(cold_cloud, qc[v]);
      cold_rain = std::max(cold_rain, qr[v]);
    }
  }
  EXPECT_GT(cold_cloud, 5e-5f);
  EXPECT_GT(cold_rain, 5e-5f);
}

TEST(WrfLoader, HurricaneHasClearEyeInsideEyewall) {
  ScratchDir dir("io");
  const std::string path = dir.file("wrfout.nc");
  auto spec = smallSpec();
  spec.ntimes = 1;
  spec.nx = 80;
  spec.ny = 80;
  spec.dx_m = 5000.0;
  const auto truth = datagen::writeWrfHurricane(spec, path);
  const ModelTimestep ts = loadWrfTimestep(path, 0);
  // Column condensate [kg/kg summed over levels] at the storm centre and on the eyewall ring.
  auto column = [&](double x_m, double y_m) {
    const int i = static_cast<int>(std::lround(x_m / spec.dx_m)), j = static_cast<int>(std::lround(y_m / spec.dx_m));
    double sum = 0.0;
    for (const auto& [h, q] : ts.q_kg_per_kg)
      for (int k = 0; k < ts.nz; ++k) sum += double(q[ts.index(i, j, k)]);
    return sum;
  };
  const double cx = truth.storm_centre_x_m, cy = truth.storm_centre_y_m;
  const double eye = column(cx, cy);
  double eyewall = 0.0;
  for (int a = 0; a < 8; ++a) {
    const double phi = a * std::numbers::pi / 4.0;
    eyewall += column(cx + 45000.0 * std::cos(phi), cy + 45000.0 * std::sin(phi)) / 8.0;
  }
  EXPECT_GT(eyewall, 10.0 * eye);
  EXPECT_GT(eyewall, 5e-3);
}

TEST(WrfLoader, TimesAndSeriesOfFiles) {
  ScratchDir dir("io");
  auto spec = smallSpec();
  spec.keep_truth = false;
  spec.nx = 16;
  spec.ny = 12;
  spec.nz = 6;
  spec.ntimes = 3;
  spec.first_hour = 3;
  const std::string later = dir.file("wrfout_d01_2026-09-01_15:00:00");
  datagen::writeWrfHurricane(spec, later);
  spec.first_hour = 0;
  const std::string earlier = dir.file("wrfout_d01_2026-09-01_12:00:00");
  datagen::writeWrfHurricane(spec, earlier);

  const auto times = listWrfTimes(earlier);
  ASSERT_EQ(times.size(), 3u);
  EXPECT_EQ(nph::geo::isoOrEmpty(times[0]), "2026-09-01T12:00:00Z");
  EXPECT_EQ(nph::geo::isoOrEmpty(times[2]), "2026-09-01T14:00:00Z");

  const ModelSeries series = ModelSeries::open({later, earlier});
  ASSERT_EQ(series.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(nph::geo::isoOrEmpty(series.at(i).time_utc), fmt::format("2026-09-01T{:02d}:00:00Z", 12 + i));
    EXPECT_EQ(series.at(i).file, i < 3 ? earlier : later);
    EXPECT_EQ(series.at(i).index, std::int64_t(i % 3));
  }
  const ModelTimestep ts = series.load(4);
  EXPECT_EQ(nph::geo::isoOrEmpty(ts.time_utc), "2026-09-01T16:00:00Z");
  EXPECT_EQ(ts.source_file, later);
  EXPECT_EQ(ts.time_index, 1);
  EXPECT_EQ(ts.model, ModelKind::Wrf);
}

TEST(WrfLoader, IdealizedRunWithoutGeolocationLoadsAsCartesian) {
  ScratchDir dir("io");
  const std::string path = dir.file("wrfout_ideal.nc");
  auto spec = smallSpec();
  spec.projection = datagen::WrfProjection::Cartesian;
  spec.ntimes = 1;
  datagen::writeWrfHurricane(spec, path);
  const ModelFile file = openModelFile(path);
  EXPECT_EQ(file.format(), FileFormat::WrfOut);
  const ModelTimestep ts = file.load(0);
  EXPECT_TRUE(ts.georef.proj_definition.empty());
  EXPECT_TRUE(ts.georef.lat_deg.empty());
  EXPECT_FALSE(ts.georef.geographic);
  EXPECT_DOUBLE_EQ(ts.georef.dx_m, 15000.0);
  EXPECT_DOUBLE_EQ(ts.georef.x0, 0.0);
}

}  // namespace
}  // namespace nph::io
