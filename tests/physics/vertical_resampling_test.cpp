// Vertical resampling onto the uniform grid: crop height, terrain, exactness on linear profiles.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

#include "core/error.h"
#include "physics/vertical_resampling.h"
#include "physics/volume_builder.h"

namespace nph::physics {
namespace {

/// Two columns on 10 levels. Column 0: terrain 0 m, h_k = 50 + 400k. Column 1: terrain 300 m,
/// h_k = 320 + 380k + 10k² (non-uniform).
io::ModelTimestep twoColumns() {
  io::ModelTimestep ts;
  ts.source_file = "columns.nc";
  ts.nx = 2;
  ts.ny = 1;
  ts.nz = 10;
  ts.terrain_height_m = {0.0f, 300.0f};
  ts.height_m.resize(ts.voxelCount());
  for (int k = 0; k < ts.nz; ++k) {
    ts.height_m[ts.index(0, 0, k)] = float(50 + 400 * k);
    ts.height_m[ts.index(1, 0, k)] = float(320 + 380 * k + 10 * k * k);
  }
  return ts;
}

// 700 hPa, 280 K and 5 g/kg of vapour in every voxel: the air the optics need.
void addUniformAir(io::ModelTimestep& ts) {
  const std::size_t n = ts.voxelCount();
  ts.pressure_pa.assign(n, 70000.0f);
  ts.temperature_k.assign(n, 280.0f);
  ts.water_vapour_kg_per_kg.assign(n, 0.005f);
}

ModelLevelExtinction emptyBeta(const io::ModelTimestep& ts) {
  ModelLevelExtinction b;
  b.nx = ts.nx;
  b.ny = ts.ny;
  b.nz = ts.nz;
  b.ice_per_m.assign(ts.voxelCount(), 0.0f);
  b.water_per_m.assign(ts.voxelCount(), 0.0f);
  return b;
}

TEST(VerticalGrid, CropJustAboveHighestCondensate) {
  const io::ModelTimestep ts = twoColumns();
  ModelLevelExtinction b = emptyBeta(ts);
  b.water_per_m[ts.index(0, 0, 3)] = 0.01f;  // column 0 clears at h_4 = 1650 m
  b.ice_per_m[ts.index(1, 0, 5)] = 0.02f;    // column 1 clears at h_6 = 320+2280+360 = 2960 m
  b.ice_per_m[ts.index(1, 0, 9)] = 1e-7f;    // below the crop threshold: ignored
  EXPECT_DOUBLE_EQ(*condensateTopHeight_m(ts, b, 1e-6), 2960.0);
  VerticalGridOptions o;
  o.dz_m = 250.0;
  const VerticalGrid g = planVerticalGrid(ts, b, o);
  EXPECT_EQ(g.z_bottom_m, 0.0);
  // centres 125, 375, ..., 2875 lie below 2960 (12 layers), plus one empty guard layer
  EXPECT_EQ(g.nz, 13);

  ExtinctionVolumes v;
  resampleVertically(ts, b, g, v);
  EXPECT_GT(v.ice_per_m[v.index(1, 0, 11)], 0.0f);                   // 2875 m lies in (h_5, h_6) of column 1
  EXPECT_EQ(v.ice_per_m[v.index(1, 0, 12)], 0.0f) << "guard layer";  // 3125 m
  EXPECT_GT(v.water_per_m[v.index(0, 0, 5)], 0.0f);                  // 1375 m: between h_3 = 1250, h_4 = 1650
  EXPECT_EQ(v.water_per_m[v.index(0, 0, 7)], 0.0f);                  // 1875 m: above h_4, column 0 is clear
}

TEST(VerticalGrid, EmptySceneKeepsOneLayerAndFixedTopOverrides) {
  const io::ModelTimestep ts = twoColumns();
  const ModelLevelExtinction b = emptyBeta(ts);
  VerticalGridOptions o;
  o.dz_m = 500.0;
  EXPECT_FALSE(condensateTopHeight_m(ts, b, 1e-6).has_value());
  EXPECT_EQ(planVerticalGrid(ts, b, o).nz, 1);
  o.z_top_m = 4200.0;
  EXPECT_EQ(planVerticalGrid(ts, b, o).nz, 9);  // ceil(4200 / 500)
  o.z_bottom_m = -1000.0;
  EXPECT_EQ(planVerticalGrid(ts, b, o).nz, 11);
  o.dz_m = 0.0;
  EXPECT_THROW((void)planVerticalGrid(ts, b, o), UsageError);
}

TEST(VerticalGrid, BottomFromLowestTerrain) {
  io::ModelTimestep ts = twoColumns();
  ts.terrain_height_m = {620.0f, 880.0f};
  EXPECT_EQ(defaultBottomHeight_m(ts, 250.0), 500.0);
  ts.terrain_height_m = {-30.0f, 880.0f};  // below sea level
  EXPECT_EQ(defaultBottomHeight_m(ts, 250.0), -250.0);
  ts.terrain_height_m.clear();                          // idealized run without HGT: half a layer below h_0
  EXPECT_EQ(defaultBottomHeight_m(ts, 100.0), -200.0);  // column 0: 50 - 200 = -150
}

TEST(Resampling, ExactOnLinearProfilesAndZeroBelowTerrain) {
  const io::ModelTimestep ts = twoColumns();
  ModelLevelExtinction b = emptyBeta(ts);
  auto ice = [](double z) { return 1e-3 + 2e-6 * z; };
  auto water = [](double z) { return 0.05 - 1e-5 * z; };  // > 0 below 5000 m
  for (int i = 0; i < 2; ++i) {
    for (int k = 0; k < ts.nz; ++k) {
      const std::size_t m = ts.index(i, 0, k);
      b.ice_per_m[m] = float(ice(double(ts.height_m[m])));
      b.water_per_m[m] = float(water(double(ts.height_m[m])));
    }
  }
  VerticalGrid g;
  g.z_bottom_m = 0.0;
  g.dz_m = 100.0;
  g.nz = 40;
  ExtinctionVolumes v;
  resampleVertically(ts, b, g, v);
  for (int i = 0; i < 2; ++i) {
    const double surface = double(ts.terrain_height_m[std::size_t(i)]);
    const double h0 = double(ts.height_m[ts.index(i, 0, 0)]);
    const double top = double(ts.height_m[ts.index(i, 0, ts.nz - 1)]);
    for (int k = 0; k < g.nz; ++k) {
      const double z = v.layerCentreHeight_m(k);
      const std::size_t q = v.index(i, 0, k);
      if (z < surface) {
        EXPECT_EQ(v.ice_per_m[q], 0.0f) << "below terrain, column " << i << " z " << z;
        EXPECT_EQ(v.water_per_m[q], 0.0f);
      } else if (z <= h0) {  // between the ground and the first mass level: lowest value
        EXPECT_EQ(v.ice_per_m[q], b.ice_per_m[ts.index(i, 0, 0)]);
      } else if (z < top) {
        EXPECT_NEAR(double(v.ice_per_m[q]), ice(z), 1e-6 * ice(z)) << i << " " << z;
        EXPECT_NEAR(double(v.water_per_m[q]), water(z), 1e-6 * water(z)) << i << " " << z;
      }
    }
  }
}

TEST(Resampling, NonIncreasingHeightsAreInputErrors) {
  io::ModelTimestep ts = twoColumns();
  ModelLevelExtinction b = emptyBeta(ts);
  b.water_per_m[ts.index(1, 0, 2)] = 0.01f;
  ts.height_m[ts.index(1, 0, 4)] = ts.height_m[ts.index(1, 0, 3)];
  VerticalGrid g{0.0, 250.0, 10};
  ExtinctionVolumes v;
  try {
    resampleVertically(ts, b, g, v);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("columns.nc"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("i=1, j=0"), std::string::npos) << e.what();
  }
}

TEST(VolumeBuilder, WholeTimestepWithGeoreference) {
  io::ModelTimestep ts = twoColumns();
  ts.time_utc = nph::geo::UtcTime::parse("2026-09-01T06:00:00Z");
  ts.time_index = 6;
  ts.georef.proj_definition = "+proj=merc +R=6370000";
  ts.georef.dx_m = 3000.0;
  ts.georef.lat_deg = {10.0f, 10.1f};
  ts.georef.lon_deg = {-60.0f, -60.0f};
  const std::size_t n = ts.voxelCount();
  addUniformAir(ts);
  ts.q_kg_per_kg[io::Hydrometeor::Cloud].assign(n, 0.0f);
  ts.q_kg_per_kg[io::Hydrometeor::Cloud][ts.index(0, 0, 2)] = 5e-4f;  // at 850 m
  VerticalGridOptions o;
  o.dz_m = 100.0;
  const ExtinctionVolumes v = buildExtinctionVolumes(ts, defaultOptics(), o);
  EXPECT_EQ(v.time_utc, ts.time_utc);
  EXPECT_EQ(v.source_time_index, 6);
  EXPECT_EQ(v.georef.proj_definition, ts.georef.proj_definition);
  EXPECT_EQ(v.georef.lat_deg, ts.georef.lat_deg);
  EXPECT_EQ(v.nz, 13);  // clears at h_3 = 1250 m: 12 centres below it + guard
  // the layer centred at 850 m (the mass level itself) has the model-level β exactly
  const double rho = 70000.0 / (287.05 * 280.0 * (1.0 + double(0.005f) / (287.05 / 461.5)));
  const double beta = 1.5 * rho * double(5e-4f) / (1000.0 * 10e-6);
  EXPECT_NEAR(double(v.water_per_m[v.index(0, 0, 8)]), beta, 1e-6 * beta);
  EXPECT_NEAR(double(v.max_water_per_m), beta, 1e-6 * beta);
  EXPECT_EQ(v.max_ice_per_m, 0.0f);
}

// The sub-grid detail's fields (TKE, cloud fraction, U, V, W), distinct values per voxel.
void addDetailFields(io::ModelTimestep& ts) {
  for (std::size_t m = 0; m < ts.voxelCount(); ++m) {
    ts.tke_m2_per_s2.push_back(0.1f * float(m));
    ts.cloud_fraction.push_back(float(m % 3) / 2.0f);
    ts.wind_u_m_per_s.push_back(float(m) - 4.0f);
    ts.wind_v_m_per_s.push_back(2.0f * float(m));
    ts.wind_w_m_per_s.push_back(0.01f * float(m));
  }
}

// The overload that takes the timestep over (`nephele convert`, issue 19) frees each model field
// after its last stage and gives the const overload's volumes bit for bit, detail fields included.
TEST(VolumeBuilder, GivenUpTimestepGivesTheSameVolumesAndFreesItsFields) {
  io::ModelTimestep ts = twoColumns();
  const std::size_t n = ts.voxelCount();
  addUniformAir(ts);
  for (auto h : {io::Hydrometeor::Cloud, io::Hydrometeor::Ice}) ts.q_kg_per_kg[h].assign(n, 0.0f);
  ts.q_kg_per_kg[io::Hydrometeor::Cloud][ts.index(0, 0, 2)] = 5e-4f;
  ts.q_kg_per_kg[io::Hydrometeor::Ice][ts.index(1, 0, 5)] = 2e-4f;
  ts.number_per_kg[io::Hydrometeor::Ice].assign(n, 1e5f);
  addDetailFields(ts);
  VerticalGridOptions o;
  o.dz_m = 100.0;
  const ExtinctionVolumes kept = buildExtinctionVolumes(ts, defaultOptics(), o);
  const std::vector<float> heights = ts.height_m;
  const ExtinctionVolumes given = buildExtinctionVolumes(std::move(ts), defaultOptics(), o);
  EXPECT_EQ(given.nz, kept.nz);
  EXPECT_EQ(given.ice_per_m, kept.ice_per_m);
  EXPECT_EQ(given.water_per_m, kept.water_per_m);
  EXPECT_EQ(given.tke_m2_per_s2, kept.tke_m2_per_s2);
  EXPECT_EQ(given.cloud_fraction, kept.cloud_fraction);
  EXPECT_EQ(given.wind_u_m_per_s, kept.wind_u_m_per_s);
  EXPECT_EQ(given.wind_v_m_per_s, kept.wind_v_m_per_s);
  EXPECT_EQ(given.wind_w_m_per_s, kept.wind_w_m_per_s);
  EXPECT_GT(kept.max_ice_per_m, 0.0f);
  EXPECT_FALSE(kept.wind_u_m_per_s.empty());
  // What the overload left behind (the point of the test, not a use after move by mistake):
  EXPECT_TRUE(ts.q_kg_per_kg.empty());
  EXPECT_TRUE(ts.number_per_kg.empty());
  EXPECT_EQ(ts.pressure_pa.capacity(), 0u);
  EXPECT_EQ(ts.temperature_k.capacity(), 0u);
  EXPECT_EQ(ts.water_vapour_kg_per_kg.capacity(), 0u);
  EXPECT_EQ(ts.wind_u_m_per_s.capacity(), 0u);
  EXPECT_EQ(ts.tke_m2_per_s2.capacity(), 0u);
  EXPECT_EQ(ts.height_m, heights);  // not the optics' alone: kept
}

// A timestep whose detail fields were deferred (io::LoadOptions::defer_detail): the builder asks
// for them once the optics' fields are freed — the point: they then reuse that memory — and gives
// the volumes of the whole timestep bit for bit. Without a loader it refuses.
TEST(VolumeBuilder, DeferredDetailFieldsAreLoadedAfterTheOpticsFieldsAreFreed) {
  io::ModelTimestep whole = twoColumns();
  const std::size_t n = whole.voxelCount();
  addUniformAir(whole);
  whole.q_kg_per_kg[io::Hydrometeor::Cloud].assign(n, 0.0f);
  whole.q_kg_per_kg[io::Hydrometeor::Cloud][whole.index(0, 0, 2)] = 5e-4f;
  addDetailFields(whole);
  VerticalGridOptions o;
  o.dz_m = 100.0;
  const ExtinctionVolumes expected = buildExtinctionVolumes(whole, defaultOptics(), o);
  io::ModelTimestep part = whole;
  for (auto* f :
       {&part.tke_m2_per_s2, &part.cloud_fraction, &part.wind_u_m_per_s, &part.wind_v_m_per_s, &part.wind_w_m_per_s}) {
    std::vector<float>().swap(*f);
  }
  part.detail_deferred = true;
  EXPECT_THROW((void)buildExtinctionVolumes(part, defaultOptics(), o), UsageError);
  int calls = 0;
  const ExtinctionVolumes got =
      buildExtinctionVolumes(std::move(part), defaultOptics(), o, [&](io::ModelTimestep& fields) {
        ++calls;
        EXPECT_TRUE(fields.q_kg_per_kg.empty()) << "the optics' fields must be freed first";
        EXPECT_EQ(fields.pressure_pa.capacity(), 0u);
        EXPECT_EQ(fields.temperature_k.capacity(), 0u);
        fields.tke_m2_per_s2 = whole.tke_m2_per_s2;
        fields.cloud_fraction = whole.cloud_fraction;
        fields.wind_u_m_per_s = whole.wind_u_m_per_s;
        fields.wind_v_m_per_s = whole.wind_v_m_per_s;
        fields.wind_w_m_per_s = whole.wind_w_m_per_s;
        fields.detail_deferred = false;
      });
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(got.water_per_m, expected.water_per_m);
  EXPECT_EQ(got.tke_m2_per_s2, expected.tke_m2_per_s2);
  EXPECT_EQ(got.cloud_fraction, expected.cloud_fraction);
  EXPECT_EQ(got.wind_u_m_per_s, expected.wind_u_m_per_s);
  EXPECT_EQ(got.wind_v_m_per_s, expected.wind_v_m_per_s);
  EXPECT_EQ(got.wind_w_m_per_s, expected.wind_w_m_per_s);
  EXPECT_FALSE(expected.wind_w_m_per_s.empty());
}

}  // namespace
}  // namespace nph::physics
