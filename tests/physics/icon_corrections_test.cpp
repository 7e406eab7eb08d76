// Muth 2026 §3.3.1 condensate consistency corrections, cell by cell (values by hand).
#include <gtest/gtest.h>

#include "physics/extinction.h"
#include "physics/icon_corrections.h"

namespace nph::physics {
namespace {

struct Cell {
  const char* what;
  double qc, qi, clc, t_k, p_pa;
  double want_qc, want_qi, want_clc;
};

TEST(IconCorrections, CellByCell) {
  const IconCorrections on;  // both corrections, Q_crit = 3e-5
  const Cell cells[] = {
      // CLC = 0 with condensate: CLC_diag = min(6e-5/3e-5, 1) = 1; bound 3e-5 < qc
      {"clc0 thick", 6e-5, 0.0, 0.0, 280.0, 9e4, 6e-5, 0.0, 1.0},
      // CLC_diag = 1.5e-5/3e-5 = 0.5; bound 1.5e-5 liquid = qc: unchanged
      {"clc0 thin", 1.5e-5, 0.0, 0.0, 280.0, 9e4, 1.5e-5, 0.0, 0.5},
      // CLC > 0, no condensate, -19 °C: f_ice = 19/38 = 0.5, q_w = 3e-5·0.8 = 2.4e-5
      {"depleted mixed", 0.0, 0.0, 0.8, 254.15, 5e4, 1.2e-5, 1.2e-5, 0.8},
      // warm: all liquid
      {"depleted warm", 0.0, 0.0, 0.4, 290.0, 9e4, 1.2e-5, 0.0, 0.4},
      // below -38 °C: all ice
      {"depleted cold", 0.0, 0.0, 0.5, 200.0, 2e4, 0.0, 1.5e-5, 0.5},
      // existing condensate above the bound stays; the other phase is raised to its share
      {"partial", 5e-5, 0.0, 1.0, 254.15, 5e4, 5e-5, 1.5e-5, 1.0},
      // validity gates: T <= 180 K, p <= 100 Pa
      {"too cold", 0.0, 0.0, 0.8, 170.0, 5e4, 0.0, 0.0, 0.8},
      {"too thin", 0.0, 0.0, 0.8, 250.0, 50.0, 0.0, 0.0, 0.8},
      // clear sky stays clear
      {"clear", 0.0, 0.0, 0.0, 280.0, 9e4, 0.0, 0.0, 0.0},
  };
  for (const Cell& c : cells) {
    const IconCellCondensate r = correctIconCell(c.qc, c.qi, c.clc, c.t_k, c.p_pa, on);
    EXPECT_NEAR(r.cloud_kg_per_kg, c.want_qc, 1e-15) << c.what;
    EXPECT_NEAR(r.ice_kg_per_kg, c.want_qi, 1e-15) << c.what;
    EXPECT_NEAR(r.cloud_cover, c.want_clc, 1e-12) << c.what;
  }
}

TEST(IconCorrections, EachCanBeSwitchedOff) {
  IconCorrections no_diag;
  no_diag.diagnose_cloud_cover = false;
  // without correction 1, CLC stays 0 and correction 2 has nothing to reconstruct from
  IconCellCondensate r = correctIconCell(1e-5, 0.0, 0.0, 250.0, 5e4, no_diag);
  EXPECT_EQ(r.cloud_cover, 0.0);
  EXPECT_EQ(r.ice_kg_per_kg, 0.0);
  // with it, CLC_eff = 1/3 and 1e-5 is split: f_ice = 23.15/38
  r = correctIconCell(1e-5, 0.0, 0.0, 250.0, 5e4, IconCorrections{});
  EXPECT_NEAR(r.cloud_cover, 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(r.ice_kg_per_kg, 1e-5 * 23.15 / 38.0, 1e-15);
  EXPECT_NEAR(r.cloud_kg_per_kg, 1e-5, 1e-15);

  IconCorrections no_rec;
  no_rec.reconstruct_condensate = false;
  r = correctIconCell(0.0, 0.0, 0.8, 254.15, 5e4, no_rec);
  EXPECT_EQ(r.cloud_kg_per_kg, 0.0);
  EXPECT_EQ(r.ice_kg_per_kg, 0.0);
}

TEST(IconCorrections, AppliedToIconFieldsOnlyWithCloudCover) {
  io::ModelTimestep ts;
  ts.source_file = "icon_tiny.nc";
  ts.model = io::ModelKind::Icon;
  ts.nx = 2;
  ts.ny = 1;
  ts.nz = 1;
  ts.pressure_pa = {50000.0f, 50000.0f};
  ts.temperature_k = {254.15f, 254.15f};
  ts.water_vapour_kg_per_kg = {0.0f, 0.0f};
  ts.height_m = {5000.0f, 5000.0f};
  ts.q_kg_per_kg[io::Hydrometeor::Cloud] = {0.0f, 0.0f};
  ts.cloud_cover_fraction = {0.8f, 0.0f};  // cell 0: depleted condensate
  const OpticsSettings s = defaultOptics();
  const ModelLevelExtinction b = modelLevelExtinction(ts, s);
  // cell 0: qc = qi = 1.2e-5 (see CellByCell), ρ = p / (R_d T)
  const double rho = 50000.0 / (287.05 * double(254.15f));
  const double clc = double(0.8f);
  EXPECT_NEAR(b.water_per_m[0], 1.5 * rho * 0.5 * 3e-5 * clc / (1000.0 * 10e-6), 1e-7);
  EXPECT_NEAR(b.ice_per_m[0], 1.5 * rho * 0.5 * 3e-5 * clc / (917.0 * 30e-6), 1e-7);
  EXPECT_EQ(b.water_per_m[1], 0.0f);
  EXPECT_EQ(b.ice_per_m[1], 0.0f);

  OpticsSettings off = s;
  off.icon.reconstruct_condensate = false;
  EXPECT_EQ(modelLevelExtinction(ts, off).water_per_m[0], 0.0f);

  ts.model = io::ModelKind::Wrf;  // never applied to WRF
  EXPECT_EQ(modelLevelExtinction(ts, s).water_per_m[0], 0.0f);
}

}  // namespace
}  // namespace nph::physics
