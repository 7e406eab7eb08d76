// Round trip generator (data_tools) -> NetCDF file -> loader (io/) -> optics (physics/) for
// chosen voxels, against β computed here independently from the raw NetCDF values (read with
// NetCDF-C) and the generator's double-precision truth for p and T.
#include <gtest/gtest.h>
#include <netcdf.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "io/model_file.h"
#include "physics/extinction.h"
#include "physics/volume_builder.h"
#include "support/scratch_dir.h"
#include "wrf_hurricane.h"

namespace nph::physics {
namespace {

namespace fs = std::filesystem;

/// One timestep of a 4-D WRF variable (Time, bottom_top, south_north, west_east), raw.
std::vector<float> readWrf(const std::string& path, const char* var, std::size_t t, const datagen::WrfTruth& truth) {
  int nc = -1, id = -1;
  EXPECT_EQ(nc_open(path.c_str(), NC_NOWRITE, &nc), NC_NOERR);
  if (nc_inq_varid(nc, var, &id) != NC_NOERR) {
    nc_close(nc);
    return {};
  }
  const std::size_t start[4] = {t, 0, 0, 0};
  const std::size_t count[4] = {1, std::size_t(truth.nz), std::size_t(truth.ny), std::size_t(truth.nx)};
  std::vector<float> v(count[1] * count[2] * count[3]);
  EXPECT_EQ(nc_get_vara_float(nc, id, start, count, v.data()), NC_NOERR) << var;
  nc_close(nc);
  return v;
}

constexpr double kRd = 287.05, kRv = 461.5, kPi = 3.14159265358979323846;

struct ClassRef {
  const char* q_name;
  const char* n_name;  // "" when the scheme has no number concentration
  double rho, r_default, mu, r_min, r_max;
  bool ice;
};

/// β [1/m] of one voxel from raw values: Nes 2008 eq. 5.3 with ρ_d = p/(R_d T (1 + r_v/ε)) and
/// r_eff = (μ+3)/(2λ), λ³ = (π/6) ρ_p (N/q)(μ+1)(μ+2)(μ+3), clamped (the default preset).
std::pair<double, double> expectedBeta(double p, double t, double qv, const std::map<std::string, double>& q,
                                       const std::map<std::string, double>& n) {
  const ClassRef classes[] = {
      {"QCLOUD", "QNCLOUD", 1000.0, 10e-6, 5.0, 2e-6, 50e-6, false},
      {"QRAIN", "QNRAIN", 1000.0, 0.5e-3, 0.0, 50e-6, 3e-3, false},
      {"QICE", "QNICE", 917.0, 30e-6, 0.0, 5e-6, 250e-6, true},
      {"QSNOW", "QNSNOW", 100.0, 0.5e-3, 0.0, 50e-6, 5e-3, true},
      {"QGRAUP", "QNGRAUPEL", 400.0, 1e-3, 0.0, 100e-6, 5e-3, true},
  };
  const double rho_d = p / (kRd * t * (1.0 + qv * kRv / kRd));
  double ice = 0.0, water = 0.0;
  for (const ClassRef& c : classes) {
    const auto qi = q.find(c.q_name);
    if (qi == q.end() || !(qi->second > 0.0)) continue;
    double r = c.r_default;
    const auto ni = n.find(c.n_name);
    if (ni != n.end() && ni->second > 0.0) {
      const double lambda =
          std::cbrt(kPi / 6.0 * c.rho * (ni->second / qi->second) * (c.mu + 1) * (c.mu + 2) * (c.mu + 3));
      r = std::clamp((c.mu + 3.0) / (2.0 * lambda), c.r_min, c.r_max);
    }
    (c.ice ? ice : water) += 1.5 * rho_d * qi->second / (c.rho * r);
  }
  return {ice, water};
}

TEST(RoundTrip, ThompsonWrfChosenVoxels) {
  test::ScratchDir dir("physics");
  datagen::WrfHurricaneSpec spec;
  spec.keep_truth = true;
  const std::string path = dir.file("wrfout_thompson.nc");
  const datagen::WrfTruth truth = datagen::writeWrfHurricane(spec, path);
  const std::size_t t = 2;
  const io::ModelTimestep ts = io::openModelFile(path).load(t);
  const ModelLevelExtinction b = modelLevelExtinction(ts, defaultOptics());

  const char* q_names[] = {"QCLOUD", "QRAIN", "QICE", "QSNOW", "QGRAUP"};
  const char* n_names[] = {"QNCLOUD", "QNRAIN", "QNICE", "QNSNOW", "QNGRAUPEL"};
  std::map<std::string, std::vector<float>> raw;
  for (const char* name : q_names) raw[name] = readWrf(path, name, t, truth);
  for (const char* name : n_names) raw[name] = readWrf(path, name, t, truth);
  const std::vector<float> qv = readWrf(path, "QVAPOR", t, truth);
  ASSERT_FALSE(raw["QCLOUD"].empty());

  // chosen voxels: the maximum of each class, and a random sample of cloudy voxels
  std::vector<std::size_t> voxels;
  for (const char* name : q_names) {
    const auto& v = raw[name];
    voxels.push_back(std::size_t(std::max_element(v.begin(), v.end()) - v.begin()));
  }
  std::mt19937 rng(5);
  std::uniform_int_distribution<std::size_t> any(0, ts.voxelCount() - 1);
  while (voxels.size() < 40) {
    const std::size_t m = any(rng);
    if (b.ice_per_m[m] + b.water_per_m[m] > 0.0f) voxels.push_back(m);
  }
  for (std::size_t m : voxels) {
    std::map<std::string, double> q, n;
    for (const char* name : q_names) q[name] = double(raw[name][m]);
    for (const char* name : n_names) n[name] = double(raw[name][m]);
    const auto [ice, water] = expectedBeta(truth.pressure_pa[t][m], truth.temperature_k[t][m], double(qv[m]), q, n);
    // float storage of p, θ and the Exner function in the file: ~1e-5 relative
    EXPECT_NEAR(double(b.ice_per_m[m]), ice, 2e-4 * ice + 1e-12) << "voxel " << m;
    EXPECT_NEAR(double(b.water_per_m[m]), water, 2e-4 * water + 1e-12) << "voxel " << m;
  }
}

TEST(RoundTrip, Wsm3FrozenCondensateIsIce) {
  test::ScratchDir dir("physics");
  datagen::WrfHurricaneSpec spec;
  spec.scheme = datagen::WrfScheme::Wsm3Like;
  spec.keep_truth = true;
  const std::string path = dir.file("wrfout_wsm3.nc");
  const datagen::WrfTruth truth = datagen::writeWrfHurricane(spec, path);
  ASSERT_EQ(truth.mp_physics, 3);
  const io::ModelTimestep ts = io::openModelFile(path).load(0);
  ASSERT_EQ(ts.microphysics_scheme, 3);
  const ModelLevelExtinction b = modelLevelExtinction(ts, defaultOptics());
  const std::vector<float> qc = readWrf(path, "QCLOUD", 0, truth);
  const std::vector<float> qr = readWrf(path, "QRAIN", 0, truth);
  const std::vector<float> qv = readWrf(path, "QVAPOR", 0, truth);
  std::size_t cold = 0, warm = 0;
  for (std::size_t m = 0; m < ts.voxelCount(); ++m) {
    const double tk = truth.temperature_k[0][m];
    if (qc[m] <= 0.0f && qr[m] <= 0.0f) continue;
    if (std::abs(tk - 273.15) < 0.05) continue;  // float T in the file could straddle 0 °C
    const double rho_d = truth.pressure_pa[0][m] / (kRd * tk * (1.0 + double(qv[m]) * kRv / kRd));
    if (tk < 273.15) {  // QCLOUD is cloud ice (917, 30 µm), QRAIN is snow (100, 0.5 mm)
      ++cold;
      const double ice = 1.5 * rho_d * (double(qc[m]) / (917.0 * 30e-6) + double(qr[m]) / (100.0 * 0.5e-3));
      ASSERT_EQ(b.water_per_m[m], 0.0f) << m;
      ASSERT_NEAR(double(b.ice_per_m[m]), ice, 2e-4 * ice) << m;
    } else {
      ++warm;
      const double water = 1.5 * rho_d * (double(qc[m]) / (1000.0 * 10e-6) + double(qr[m]) / (1000.0 * 0.5e-3));
      ASSERT_EQ(b.ice_per_m[m], 0.0f) << m;
      ASSERT_NEAR(double(b.water_per_m[m]), water, 2e-4 * water) << m;
    }
  }
  EXPECT_GT(cold, 100u) << "the generator should put condensate above the freezing level";
  EXPECT_GT(warm, 100u);
}

TEST(RoundTrip, ResampledColumnKeepsOpticalDepthAndNoOvershoot) {
  test::ScratchDir dir("physics");
  const std::string path = dir.file("wrfout.nc");
  datagen::writeWrfHurricane(datagen::WrfHurricaneSpec{}, path);
  const io::ModelTimestep ts = io::openModelFile(path).load(3);
  const ModelLevelExtinction b = modelLevelExtinction(ts, defaultOptics());
  VerticalGridOptions o;
  o.dz_m = 50.0;
  const ExtinctionVolumes v = buildExtinctionVolumes(ts, defaultOptics(), o);
  const float model_max = std::max(*std::max_element(b.water_per_m.begin(), b.water_per_m.end()),
                                   *std::max_element(b.ice_per_m.begin(), b.ice_per_m.end()));
  EXPECT_LE(std::max(v.max_ice_per_m, v.max_water_per_m), model_max * (1.0f + 1e-6f));
  // optical depth of every cloudy column between the lowest and highest mass level:
  // PCHIP integral (fine grid) vs trapezoid on the model levels
  int checked = 0;
  for (int j = 0; j < ts.ny; ++j) {
    for (int i = 0; i < ts.nx; ++i) {
      double tau_model = 0.0, tau_grid = 0.0;
      for (int k = 0; k + 1 < ts.nz; ++k) {
        const double dh = double(ts.height_m[ts.index(i, j, k + 1)] - ts.height_m[ts.index(i, j, k)]);
        tau_model += 0.5 * dh * double(b.water_per_m[ts.index(i, j, k)] + b.water_per_m[ts.index(i, j, k + 1)]);
      }
      const double h0 = double(ts.height_m[ts.index(i, j, 0)]);
      const double htop = double(ts.height_m[ts.index(i, j, ts.nz - 1)]);
      for (int k = 0; k < v.nz; ++k) {
        const double z = v.layerCentreHeight_m(k);
        if (z > h0 && z < htop) tau_grid += double(v.water_per_m[v.index(i, j, k)]) * v.dz_m;
      }
      if (tau_model < 1.0) continue;  // thin columns: edge effects of one 50 m layer dominate
      ++checked;
      EXPECT_NEAR(tau_grid / tau_model, 1.0, 0.1) << "column " << i << "," << j;
    }
  }
  EXPECT_GT(checked, 20);
}

}  // namespace
}  // namespace nph::physics
