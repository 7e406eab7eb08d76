// Hand-computed extinction (Nes 2008 eq. 5.3) for chosen voxels, dry (WRF) vs moist (ICON) air
// density, r_eff from number concentrations, and the WSM3 ice split.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/error.h"
#include "physics/air_density.h"
#include "physics/effective_radius.h"
#include "physics/extinction.h"
#include "physics/optics_settings.h"

namespace nph::physics {
namespace {

using io::Hydrometeor;
constexpr std::size_t idx(Hydrometeor h) { return static_cast<std::size_t>(h); }

// Values computed by hand (Python, double) from the formulas in air_density.h:
//   R_d = 287.05, R_v = 461.5, ε = R_d/R_v; p = 80000 Pa, T = 270 K, vapour 0.004, qc = 1e-3.
//   WRF  ρ_d = p / (R_d T (1 + r_v/ε))                 = 1.0256157797141403 kg/m³
//   ICON ρ   = p / (R_d T (1 + (1/ε - 1) q_v - q_c))    = 1.0307365311483265 kg/m³
//   β = 3 ρ q / (2 · 1000 kg/m³ · 10 µm): WRF 0.15384236695712103 /m, ICON 0.154610479672249 /m
TEST(AirDensity, DryAndMoistHandComputed) {
  EXPECT_NEAR(dryAirDensity(80000.0, 270.0, 0.004), 1.0256157797141403, 1e-12);
  EXPECT_NEAR(moistAirDensity(80000.0, 270.0, 0.004, 1e-3), 1.0307365311483265, 1e-12);
  // dry air: both reduce to p / (R_d T)
  EXPECT_NEAR(dryAirDensity(100000.0, 300.0, 0.0), 100000.0 / (287.05 * 300.0), 1e-12);
  EXPECT_NEAR(moistAirDensity(100000.0, 300.0, 0.0, 0.0), 100000.0 / (287.05 * 300.0), 1e-12);
}

VoxelState cloudVoxel(io::ModelKind model) {
  VoxelState v;
  v.model = model;
  v.pressure_pa = 80000.0;
  v.temperature_k = 270.0;
  v.vapour_kg_per_kg = 0.004;
  v.q_kg_per_kg[idx(Hydrometeor::Cloud)] = 1e-3;
  return v;
}

TEST(VoxelExtinction, WrfUsesDryDensityIconMoist) {
  const OpticsSettings s = defaultOptics();
  const VoxelExtinction wrf = voxelExtinction(cloudVoxel(io::ModelKind::Wrf), s);
  EXPECT_NEAR(wrf.water_per_m, 0.15384236695712103, 1e-12);
  EXPECT_EQ(wrf.ice_per_m, 0.0);
  const VoxelExtinction icon = voxelExtinction(cloudVoxel(io::ModelKind::Icon), s);
  EXPECT_NEAR(icon.water_per_m, 0.154610479672249, 1e-12);
  EXPECT_EQ(icon.ice_per_m, 0.0);
}

TEST(VoxelExtinction, ClassesSumIntoIceAndWater) {
  const OpticsSettings s = defaultOptics();
  VoxelState v = cloudVoxel(io::ModelKind::Wrf);
  v.q_kg_per_kg[idx(Hydrometeor::Rain)] = 2e-3;
  v.q_kg_per_kg[idx(Hydrometeor::Ice)] = 1e-4;
  v.q_kg_per_kg[idx(Hydrometeor::Snow)] = 3e-4;
  v.q_kg_per_kg[idx(Hydrometeor::Graupel)] = 5e-4;
  v.q_kg_per_kg[idx(Hydrometeor::Hail)] = 7e-4;
  const VoxelExtinction e = voxelExtinction(v, s);
  const double rho = 1.0256157797141403;
  const double water = 1.5 * rho * (1e-3 / (1000 * 10e-6) + 2e-3 / (1000 * 0.5e-3));
  const double ice =
      1.5 * rho * (1e-4 / (917 * 30e-6) + 3e-4 / (100 * 0.5e-3) + 5e-4 / (400 * 1e-3) + 7e-4 / (900 * 2.5e-3));
  EXPECT_NEAR(e.water_per_m, water, 1e-12);
  EXPECT_NEAR(e.ice_per_m, ice, 1e-12);
}

TEST(VoxelExtinction, Nes2008PresetUsesTable51Radii) {
  const OpticsSettings s = nes2008Optics();
  EXPECT_DOUBLE_EQ(s[Hydrometeor::Cloud].effective_radius_m, 1e-5);
  EXPECT_DOUBLE_EQ(s[Hydrometeor::Snow].effective_radius_m, 2e-3);
  VoxelState v = cloudVoxel(io::ModelKind::Wrf);
  v.q_kg_per_kg[idx(Hydrometeor::Graupel)] = 1e-3;
  v.number_per_kg[idx(Hydrometeor::Cloud)] = 1e6;  // ignored: the preset has fixed radii
  const VoxelExtinction e = voxelExtinction(v, s);
  const double rho = 1.0256157797141403;
  EXPECT_NEAR(e.water_per_m, 1.5 * rho * 1e-3 / (1000 * 1e-5), 1e-12);
  EXPECT_NEAR(e.ice_per_m, 1.5 * rho * 1e-3 / (917 * 2.5e-3), 1e-12);
}

TEST(VoxelExtinction, NegativeMixingRatiosCountAsZero) {
  VoxelState v = cloudVoxel(io::ModelKind::Wrf);
  v.q_kg_per_kg[idx(Hydrometeor::Cloud)] = -1e-6;
  EXPECT_EQ(voxelExtinction(v, defaultOptics()).water_per_m, 0.0);
}

// --- effective radius from number concentration ---------------------------------------------

/// r_eff, q and N of a gamma distribution integrated numerically (independent of the closed
/// form in effective_radius.cpp).
struct Moments {
  double q_per_m3, number_per_m3, r_eff_m;
};
Moments integrateGamma(double n0, double mu, double lambda, double rho_p) {
  double m0 = 0, m2 = 0, m3 = 0;
  const double d_max = 60.0 / lambda, step = d_max / 200000.0;
  for (double d = 0.5 * step; d < d_max; d += step) {
    const double n = n0 * std::pow(d, mu) * std::exp(-lambda * d) * step;
    m0 += n;
    m2 += n * d * d;
    m3 += n * d * d * d;
  }
  return {rho_p * 3.14159265358979323846 / 6.0 * m3, m0, 0.5 * m3 / m2};
}

TEST(EffectiveRadius, MatchesNumericallyIntegratedGammaDistribution) {
  const double rho_air = 1.1;  // cancels: q and N are both per kg of air
  for (double mu : {0.0, 2.0, 5.0}) {
    for (double lambda : {2e3, 5e4, 2e5}) {
      const Moments m = integrateGamma(1e10, mu, lambda, 1000.0);
      const double r =
          effectiveRadiusFromNumber(m.q_per_m3 / rho_air, m.number_per_m3 / rho_air, 1000.0, mu, 1.0, 0.0, 1.0);
      EXPECT_NEAR(r / m.r_eff_m, 1.0, 1e-4) << "mu " << mu << " lambda " << lambda;
      EXPECT_NEAR(r, (mu + 3.0) / (2.0 * lambda), 1e-6 * r);
    }
  }
}

TEST(EffectiveRadius, HandComputedAndFallbacks) {
  // q = 1e-3, N = 1e8 /kg, ρ_p = 1000, μ = 0: λ³ = π·1e14 m⁻³ → r_eff = 3/(2λ) = 22.07 µm
  EXPECT_NEAR(effectiveRadiusFromNumber(1e-3, 1e8, 1000.0, 0.0, 1.0, 0.0, 1.0),
              1.5 / std::cbrt(3.14159265358979323846e14), 1e-12);
  EXPECT_EQ(effectiveRadiusFromNumber(1e-3, 0.0, 1000.0, 0.0, 7e-6, 0.0, 1.0), 7e-6);
  EXPECT_EQ(effectiveRadiusFromNumber(0.0, 1e8, 1000.0, 0.0, 7e-6, 0.0, 1.0), 7e-6);
  EXPECT_EQ(effectiveRadiusFromNumber(1e-3, std::nan(""), 1000.0, 0.0, 7e-6, 0.0, 1.0), 7e-6);
  EXPECT_EQ(effectiveRadiusFromNumber(1e-3, 1.0, 1000.0, 0.0, 7e-6, 2e-6, 50e-6), 50e-6);  // clamp
}

// The fast cube root of the effective radius (issue 19): within 1 ulp of the true root (cbrtl, 64-bit
// mantissa, rounded to double) over [2⁻¹⁰⁰⁰, 2¹⁰⁰⁰], on a log-uniform sweep and at powers of 2 and
// their neighbours (where the exponent-thirding guess is at its worst) — closer than glibc's own
// cbrt, which is not correctly rounded (cbrt(27) = 3 + 1 ulp) — and std::cbrt's result outside
// that range.
TEST(EffectiveRadius, FastCubeRootIsWithinOneUlpOfTheTrueRoot) {
  auto ulps = [](double a, double b) {
    const auto ia = std::bit_cast<std::int64_t>(a), ib = std::bit_cast<std::int64_t>(b);
    return ia > ib ? ia - ib : ib - ia;
  };
  std::int64_t worst = 0, worst_glibc = 0;
  auto check = [&](double x) {
    const auto truth = static_cast<double>(std::cbrt(static_cast<long double>(x)));
    worst = std::max(worst, ulps(cubeRootPositive(x), truth));
    worst_glibc = std::max(worst_glibc, ulps(std::cbrt(x), truth));
  };
  std::uint64_t state = 0x9E3779B97F4A7C15ull;  // xorshift64*: a fixed sweep
  for (int i = 0; i < 1000000; ++i) {
    state ^= state >> 12;
    state ^= state << 25;
    state ^= state >> 27;
    const double u = double((state * 0x2545F4914F6CDD1Dull) >> 11) * 0x1.0p-53;  // [0, 1)
    check(std::exp2(-1000.0 + u * 2000.0));
  }
  for (int e = -1000; e < 1000; ++e) {
    const double p = std::ldexp(1.0, e);
    for (double x : {p, std::nextafter(p, 1e308), 1.5 * p, 1.999999 * p, std::nextafter(2.0 * p, 0.0)}) check(x);
  }
  EXPECT_LE(worst, 1);
  // glibc's cbrt on the same sweep: 3 ulps at worst (its documented bound on x86-64 is 4).
  EXPECT_LE(worst, worst_glibc);
  for (double x : {0.0, 1e-310, 0x1.0p-1001, 0x1.0p1001, -8.0, std::numeric_limits<double>::infinity()}) {
    EXPECT_EQ(cubeRootPositive(x), std::cbrt(x)) << x;
  }
  EXPECT_TRUE(std::isnan(cubeRootPositive(std::nan(""))));
}

TEST(VoxelExtinction, CloudRadiusFromNumberConcentration) {
  const OpticsSettings s = defaultOptics();  // cloud μ = 5
  VoxelState v = cloudVoxel(io::ModelKind::Wrf);
  v.number_per_kg[idx(Hydrometeor::Cloud)] = 3e8;  // 300 per cm³ at ~1 kg/m³
  const double lambda = std::cbrt(3.14159265358979323846 / 6.0 * 1000.0 * (3e8 / 1e-3) * 6 * 7 * 8);
  const double r = 8.0 / (2.0 * lambda);
  ASSERT_GT(r, 2e-6);
  ASSERT_LT(r, 50e-6);
  const VoxelExtinction e = voxelExtinction(v, s);
  EXPECT_NEAR(e.water_per_m, 1.5 * 1.0256157797141403 * 1e-3 / (1000.0 * r), 1e-12);
  // switching number concentrations off falls back to the 10 µm default
  OpticsSettings fixed = s;
  fixed.use_number_concentrations = false;
  EXPECT_NEAR(voxelExtinction(v, fixed).water_per_m, 0.15384236695712103, 1e-12);
}

// --- WSM3: condensate split by temperature ---------------------------------------------------

TEST(VoxelExtinction, Wsm3BelowFreezingIsIce) {
  const OpticsSettings s = defaultOptics();
  VoxelState v;
  v.model = io::ModelKind::Wrf;
  v.microphysics_scheme = 3;
  v.pressure_pa = 60000.0;
  v.temperature_k = 260.0;
  v.vapour_kg_per_kg = 0.002;
  v.q_kg_per_kg[idx(Hydrometeor::Cloud)] = 1e-4;
  v.q_kg_per_kg[idx(Hydrometeor::Rain)] = 2e-4;
  // hand computed: ρ_d = 0.8013571785175372; QCLOUD as ice (917, 30 µm), QRAIN as snow (100, 0.5 mm)
  const VoxelExtinction cold = voxelExtinction(v, s);
  EXPECT_EQ(cold.water_per_m, 0.0);
  EXPECT_NEAR(cold.ice_per_m, 0.009177593335650137, 1e-12);

  v.temperature_k = 273.16;  // above freezing: liquid
  const VoxelExtinction warm = voxelExtinction(v, s);
  EXPECT_EQ(warm.ice_per_m, 0.0);
  EXPECT_GT(warm.water_per_m, 0.0);

  v.temperature_k = 260.0;
  v.microphysics_scheme = 8;  // Thompson has separate ice: QCLOUD is supercooled water
  const VoxelExtinction thompson = voxelExtinction(v, s);
  EXPECT_EQ(thompson.ice_per_m, 0.0);
  EXPECT_GT(thompson.water_per_m, 0.0);

  v.microphysics_scheme = 3;
  v.model = io::ModelKind::Icon;  // the scheme number is a WRF notion
  EXPECT_EQ(voxelExtinction(v, s).ice_per_m, 0.0);
}

// --- whole fields ---------------------------------------------------------------------------

io::ModelTimestep tinyTimestep() {
  io::ModelTimestep ts;
  ts.source_file = "tiny_wrfout.nc";
  ts.time_utc = nph::geo::UtcTime::parse("2026-09-01T00:00:00Z");
  ts.nx = 3;
  ts.ny = 2;
  ts.nz = 2;
  const std::size_t n = ts.voxelCount();
  ts.pressure_pa.assign(n, 80000.0f);
  ts.temperature_k.assign(n, 270.0f);
  ts.water_vapour_kg_per_kg.assign(n, 0.004f);
  ts.height_m = {100, 100, 100, 100, 100, 100, 600, 600, 600, 600, 600, 600};
  ts.q_kg_per_kg[Hydrometeor::Cloud].assign(n, 0.0f);
  ts.q_kg_per_kg[Hydrometeor::Cloud][ts.index(2, 1, 1)] = 1e-3f;
  return ts;
}

TEST(ModelLevelExtinction, ChosenVoxel) {
  const io::ModelTimestep ts = tinyTimestep();
  const ModelLevelExtinction b = modelLevelExtinction(ts, defaultOptics());
  const double rho = dryAirDensity(80000.0, 270.0, double(0.004f));
  EXPECT_NEAR(b.water_per_m[ts.index(2, 1, 1)], 1.5 * rho * double(1e-3f) / (1000 * 1e-5), 1e-6);
  EXPECT_EQ(b.water_per_m[ts.index(1, 1, 1)], 0.0f);
}

TEST(ModelLevelExtinction, BadFieldsAreInputErrorsNamingFileAndVariable) {
  io::ModelTimestep ts = tinyTimestep();
  ts.temperature_k[ts.index(1, 0, 1)] = std::nanf("");
  try {
    (void)modelLevelExtinction(ts, defaultOptics());
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("tiny_wrfout.nc"), std::string::npos) << msg;
    EXPECT_NE(msg.find("temperature"), std::string::npos) << msg;
    EXPECT_NE(msg.find("i=1, j=0, k=1"), std::string::npos) << msg;
  }
  ts = tinyTimestep();
  ts.pressure_pa.pop_back();
  EXPECT_THROW((void)modelLevelExtinction(ts, defaultOptics()), InputError);
  ts = tinyTimestep();
  ts.q_kg_per_kg[Hydrometeor::Snow].assign(3, 0.0f);
  EXPECT_THROW((void)modelLevelExtinction(ts, defaultOptics()), InputError);
}

TEST(OpticsSettings, PresetsOverridesAndJson) {
  EXPECT_EQ(opticsPreset("nes2008").preset, "nes2008");
  EXPECT_THROW((void)opticsPreset("nes2009"), UsageError);
  OpticsSettings s = defaultOptics();
  applyRadiusOverride(s, "snow=400um");
  EXPECT_NEAR(s[Hydrometeor::Snow].effective_radius_m, 4e-4, 1e-15);
  applyRadiusOverride(s, "rain=0.8mm");
  EXPECT_NEAR(s[Hydrometeor::Rain].effective_radius_m, 8e-4, 1e-15);
  EXPECT_THROW(applyRadiusOverride(s, "sleet=1mm"), UsageError);
  EXPECT_THROW(applyRadiusOverride(s, "snow=1furlong"), UsageError);
  EXPECT_THROW(applyRadiusOverride(s, "snow=-1mm"), UsageError);
  EXPECT_NE(s.toJson().find("\"snow\""), std::string::npos);
}

}  // namespace
}  // namespace nph::physics
