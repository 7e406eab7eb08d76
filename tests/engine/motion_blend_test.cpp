// Motion-compensated blending between two timesteps (engine/dataset.h TimeBlend::Motion; issue 13,
// docs/animation.md "Between two timesteps"): closed forms on small in-memory volumes, no GL.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "cache/quantize.h"
#include "engine/dataset.h"
#include "engine_test_support.h"
#include "geo/utc_time.h"
#include "wrf_hurricane.h"

namespace nph::test {
namespace {

constexpr int kNx = 48, kNy = 40, kNz = 3;
constexpr double kDx = 2000.0;  // m per column
constexpr double kDt = 3600.0;  // s between the timesteps
constexpr double kSigma = 3.0;  // the cell's Gaussian radius [columns]
constexpr double kPeak = 0.02;  // /m: 500 m of it is τ = 10, optically thick

/// Per level, the displacement of the air over Δt in columns: a wind that turns and changes with
/// height (a sheared column). The cloud column moves as one with the cloud-weighted mean of them
/// (engine/dataset.cpp steeringWinds): with the same cell at every level, their plain mean.
const double kWind[kNz][2] = {{10.0, -6.0}, {-4.0, 2.0}, {6.0, -2.0}};
const double kShift[2] = {(kWind[0][0] + kWind[1][0] + kWind[2][0]) / 3.0,
                          (kWind[0][1] + kWind[1][1] + kWind[2][1]) / 3.0};  // (4, −2) columns
const double kCentre[2] = {22.3, 19.6};  // timestep a's cell centre, ≥ 5σ from every edge at a and b

double cell(double x, double y, double cx, double cy) {
  const double r2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
  return kPeak * std::exp(-0.5 * r2 / (kSigma * kSigma));
}

/// The cell of every level moved by `share` of the column's displacement, each level with its own
/// uniform wind; water ½ and TKE 10·(the ice), cloud fraction β/peak, W 1 m/s: every field carries
/// the same shape.
ExtinctionVolumes carriedCell(double share, const char* time) {
  ExtinctionVolumes v = ExtinctionVolumes::zeros(kNx, kNy, kNz, kDx, 500.0, 1000.0);
  if (time) v.time_utc = geo::UtcTime::parse(time);
  for (auto* f : {&v.tke_m2_per_s2, &v.cloud_fraction, &v.wind_w_m_per_s, &v.wind_u_m_per_s, &v.wind_v_m_per_s})
    f->assign(v.voxelCount(), 0.0f);
  for (int k = 0; k < kNz; ++k) {
    for (int j = 0; j < kNy; ++j) {
      for (int i = 0; i < kNx; ++i) {
        const std::size_t n = v.index(i, j, k);
        const float beta = float(cell(i, j, kCentre[0] + share * kShift[0], kCentre[1] + share * kShift[1]));
        v.ice_per_m[n] = beta;
        v.water_per_m[n] = 0.5f * beta;
        v.tke_m2_per_s2[n] = 10.0f * beta;
        v.cloud_fraction[n] = float(double(beta) / kPeak);
        v.wind_w_m_per_s[n] = 1.0f;
        v.wind_u_m_per_s[n] = float(kWind[k][0] * kDx / kDt);
        v.wind_v_m_per_s[n] = float(kWind[k][1] * kDx / kDt);
      }
    }
  }
  v.updateMaxima();
  return v;
}

ExtinctionVolumes timestepA() { return carriedCell(0.0, "2026-09-01T12:00:00Z"); }
ExtinctionVolumes timestepB() { return carriedCell(1.0, "2026-09-01T13:00:00Z"); }

double levelMass(const std::vector<float>& f, int k) {
  const std::size_t layer = std::size_t(kNx) * kNy;
  double sum = 0.0;
  for (std::size_t c = 0; c < layer; ++c) sum += double(f[std::size_t(k) * layer + c]);
  return sum;
}

/// max |field − want·scale| over a level, the expected cell at `share` of the displacement.
double worstError(const std::vector<float>& f, int k, double share, double scale) {
  double worst = 0.0;
  for (int j = 0; j < kNy; ++j) {
    for (int i = 0; i < kNx; ++i) {
      const double want = scale * cell(i, j, kCentre[0] + share * kShift[0], kCentre[1] + share * kShift[1]);
      worst =
          std::max(worst, std::abs(double(f[(std::size_t(k) * kNy + std::size_t(j)) * kNx + std::size_t(i)]) - want));
    }
  }
  return worst;
}

// A cloud column in a sheared wind: the same cell at three levels whose winds differ (10, −6),
// (−4, 2), (6, −2) columns per Δt; b is the column moved as one by their cloud-weighted mean
// (4, −2). At w = ½ every level is the cell moved by (2, −1), exactly on columns: the column stays
// upright (bound: float rounding and the window's edge, 10⁻⁴ of the peak), for ice, water, TKE and
// cloud fraction; each level's optical mass within 10⁻⁵; the peak stays. Moving each level with
// its own wind (the eighteenth session's blend) put the levels (5, −3), (−2, 1) and (3, −1) columns
// away — a tower sheared into a slanted streak (docs/animation.md "Clouds move as columns"). The
// cross-fade misses by two half-weight cells 4.5 columns apart (0.24 of the peak).
TEST(MotionBlend, ACloudColumnMovesAsOneWithItsCloudWeightedWind) {
  const ExtinctionVolumes a = timestepA(), b = timestepB();
  ASSERT_TRUE(engine::blendHasMotion(a, b));
  const ExtinctionVolumes m = engine::blendVolumes(a, b, 0.5, engine::TimeBlend::Motion);
  const ExtinctionVolumes lin = engine::blendVolumes(a, b, 0.5, engine::TimeBlend::Linear);
  ASSERT_EQ(m.nz, kNz);
  const double bound = 1e-4 * kPeak;
  for (int k = 0; k < kNz; ++k) {
    SCOPED_TRACE(k);
    EXPECT_LT(worstError(m.ice_per_m, k, 0.5, 1.0), bound);
    EXPECT_LT(worstError(m.water_per_m, k, 0.5, 0.5), 0.5 * bound);
    EXPECT_LT(worstError(m.tke_m2_per_s2, k, 0.5, 10.0), 10.0 * bound);
    EXPECT_LT(worstError(m.cloud_fraction, k, 0.5, 1.0 / kPeak), bound / kPeak);
    // Mass: the level's optical mass (Σβ over its columns) is a's — the weights sum to 1 and a
    // uniform translation inside the domain keeps every read's total; float rounding only.
    EXPECT_NEAR(levelMass(m.ice_per_m, k), levelMass(a.ice_per_m, k), 1e-5 * levelMass(a.ice_per_m, k));
    EXPECT_NEAR(levelMass(m.water_per_m, k), levelMass(a.water_per_m, k), 1e-5 * levelMass(a.water_per_m, k));
    // The cross-fade fails the same check.
    EXPECT_GT(worstError(lin.ice_per_m, k, 0.5, 1.0), 0.2 * kPeak);
  }
  // The peak stays (up to the lattice's nearest point to the centre, ½ column: peak/(4σ²)): one
  // opaque cell, not two half-weight ghosts.
  EXPECT_NEAR(m.max_ice_per_m, kPeak, kPeak / (4.0 * kSigma * kSigma));
  // At w = ¼ the column is a quarter of the way ((1, −0.5) columns: bilinear reads half-way between
  // columns in y; bound the bilinear interpolation error of the Gaussian, peak/(4σ²)·¼ in y alone).
  const ExtinctionVolumes q = engine::blendVolumes(a, b, 0.25, engine::TimeBlend::Motion);
  for (int k = 0; k < kNz; ++k) EXPECT_LT(worstError(q.ice_per_m, k, 0.25, 1.0), kPeak / (8.0 * kSigma * kSigma)) << k;
  // Each level's own wind is carried as it is (uniform per level: unchanged).
  EXPECT_FLOAT_EQ(m.wind_u_m_per_s[m.index(20, 20, 1)], float(kWind[1][0] * kDx / kDt));
}

TEST(MotionBlend, TheEndsAreTheTimestepsExactly) {
  const ExtinctionVolumes a = timestepA(), b = timestepB();
  for (const double w : {0.0, -0.5}) {
    const ExtinctionVolumes m = engine::blendVolumes(a, b, w, engine::TimeBlend::Motion);
    EXPECT_EQ(m.ice_per_m, a.ice_per_m);
    EXPECT_EQ(m.water_per_m, a.water_per_m);
    EXPECT_EQ(m.tke_m2_per_s2, a.tke_m2_per_s2);
    EXPECT_EQ(m.wind_u_m_per_s, a.wind_u_m_per_s);
  }
  for (const double w : {1.0, 1.5}) {
    const ExtinctionVolumes m = engine::blendVolumes(a, b, w, engine::TimeBlend::Motion);
    EXPECT_EQ(m.ice_per_m, b.ice_per_m);
    EXPECT_EQ(m.water_per_m, b.water_per_m);
    EXPECT_EQ(m.cloud_fraction, b.cloud_fraction);
  }
}

void expectLinear(const ExtinctionVolumes& a, const ExtinctionVolumes& b, bool motion_expected) {
  EXPECT_EQ(engine::blendHasMotion(a, b), motion_expected);
  for (const double w : {0.25, 0.5, 0.75}) {
    const ExtinctionVolumes m = engine::blendVolumes(a, b, w, engine::TimeBlend::Motion);
    const ExtinctionVolumes lin = engine::blendVolumes(a, b, w, engine::TimeBlend::Linear);
    EXPECT_EQ(m.ice_per_m, lin.ice_per_m) << w;
    EXPECT_EQ(m.water_per_m, lin.water_per_m) << w;
    EXPECT_EQ(m.tke_m2_per_s2, lin.tke_m2_per_s2) << w;
    EXPECT_EQ(m.wind_v_m_per_s, lin.wind_v_m_per_s) << w;
  }
}

TEST(MotionBlend, CalmAirIsTheLinearBlendBitForBit) {
  ExtinctionVolumes a = timestepA(), b = timestepB();
  for (auto* v : {&a, &b}) {
    std::fill(v->wind_u_m_per_s.begin(), v->wind_u_m_per_s.end(), 0.0f);
    std::fill(v->wind_v_m_per_s.begin(), v->wind_v_m_per_s.end(), 0.0f);
  }
  expectLinear(a, b, true);  // it moves nothing: every read lands on its own column
}

TEST(MotionBlend, WithoutTimesOrWindsItIsTheLinearBlend) {
  const ExtinctionVolumes a = timestepA(), b = timestepB();
  {
    SCOPED_TRACE("no times");
    expectLinear(carriedCell(0.0, nullptr), carriedCell(1.0, nullptr), false);
  }
  {
    SCOPED_TRACE("b not later than a");
    expectLinear(a, carriedCell(1.0, "2026-09-01T12:00:00Z"), false);
    expectLinear(b, a, false);
  }
  {
    SCOPED_TRACE("no U, V (a .nph cache)");
    ExtinctionVolumes calm = b;
    calm.wind_u_m_per_s.clear();
    calm.wind_v_m_per_s.clear();
    expectLinear(a, calm, false);
  }
}

TEST(MotionBlend, AShearedWindIsFollowedAlongTheTrajectory) {
  // A wind that changes across the flow: u = u0 + S·(y − y0) (S per column), v = v0. Along a
  // trajectory y moves, so the air meets a changing u: over τ the cell's centre moves by
  // (u0·τ + S·v0·τ²/2, v0·τ) [m], where the wind read at the arrival point alone (no iteration)
  // gives u0·τ — 0.81 columns short here. The midpoint iteration is exact for this wind (the mean
  // of a linear u along the trajectory is u at its midpoint), so the centroid of what each side
  // carries lies on the exact trajectory; bound ¼ column (the bilinear reads of a sheared cell).
  const double u0 = 4.0, S = 0.5, v0 = 4.0, tau = 0.5 * kDt;                            // m/s, m/s per column, m/s, s
  const double along = v0 * tau / kDx, drift = S * v0 * tau * tau / (2.0 * kDx * kDx);  // columns
  ASSERT_NEAR(drift, 0.81, 1e-9);
  for (const bool from_a : {true, false}) {
    SCOPED_TRACE(from_a ? "a carried forwards" : "b carried backwards");
    ExtinctionVolumes a = timestepA(), b = timestepA();  // the cell at kCentre at both times
    b.time_utc = timestepB().time_utc;
    for (auto* v : {&a, &b}) {
      for (int k = 0; k < kNz; ++k) {
        for (int j = 0; j < kNy; ++j) {
          for (int i = 0; i < kNx; ++i) {
            v->wind_u_m_per_s[v->index(i, j, k)] = float(u0 + S * (j - kCentre[1]));
            v->wind_v_m_per_s[v->index(i, j, k)] = float(v0);
          }
        }
      }
    }
    ExtinctionVolumes& empty = from_a ? b : a;  // only one side's cell, to follow its trajectory
    std::fill(empty.ice_per_m.begin(), empty.ice_per_m.end(), 0.0f);
    const ExtinctionVolumes m = engine::blendVolumes(a, b, 0.5, engine::TimeBlend::Motion);
    double sum = 0.0, sx = 0.0, sy = 0.0, peak = 0.0;
    for (int j = 0; j < kNy; ++j) {
      for (int i = 0; i < kNx; ++i) {
        const double f = m.ice_per_m[m.index(i, j, 0)];
        sum += f, sx += f * i, sy += f * j, peak = std::max(peak, f);
      }
    }
    const double sign = from_a ? 1.0 : -1.0;  // b's cell is where the air goes after τ
    EXPECT_NEAR(sx / sum, kCentre[0] + sign * u0 * tau / kDx + drift, 0.25);
    EXPECT_NEAR(sy / sum, kCentre[1] + sign * along, 0.25);
    EXPECT_NEAR(sum, 0.5 * levelMass(timestepA().ice_per_m, 0), 0.01 * sum);  // half the weight, 1 %
    EXPECT_GT(peak, 0.4 * kPeak);                                             // sheared, not smeared out
  }
}

/// Mean |τ_m − τ_truth| over the columns, τ the column optical depth (ice + water) of each volume on
/// its own vertical grid (each timestep converted on the fly is cropped to its own column).
double meanColumnError(const ExtinctionVolumes& m, const ExtinctionVolumes& truth) {
  const auto tau = [](const ExtinctionVolumes& v, int i, int j) {
    double t = 0.0;
    for (int k = 0; k < v.nz; ++k)
      t += (double(v.ice_per_m[v.index(i, j, k)]) + double(v.water_per_m[v.index(i, j, k)])) * v.dz_m;
    return t;
  };
  double sum = 0.0;
  for (int j = 0; j < m.ny; ++j)
    for (int i = 0; i < m.nx; ++i) sum += std::abs(tau(m, i, j) - tau(truth, i, j));
  return sum / double(m.nx * m.ny);
}

/// A 3-timestep model file written from `spec` to `path`, converted as `nephele render` converts it:
/// the mean column error (meanColumnError) of the blends of timesteps 0 and 2 at w = ½ against
/// timestep 1, the cross-fade's and the motion blend's (printed with `name`).
struct HalfWayErrors {
  double linear = 0.0, motion = 0.0;
};
HalfWayErrors halfWayErrors(const datagen::WrfHurricaneSpec& spec, const std::string& path, const char* name) {
  datagen::writeWrfHurricane(spec, path);
  const auto ds = engine::Dataset::open(path);
  const ExtinctionVolumes a = ds->load(0), truth = ds->load(1), b = ds->load(2);
  EXPECT_TRUE(engine::blendHasMotion(a, b));
  HalfWayErrors e;
  e.linear = meanColumnError(engine::blendVolumes(a, b, 0.5, engine::TimeBlend::Linear), truth);
  e.motion = meanColumnError(engine::blendVolumes(a, b, 0.5, engine::TimeBlend::Motion), truth);
  std::printf("[ motion   ] %s: mean |tau - tau(13 UTC)| per column: linear %.4f, motion %.4f (ratio %.3f)\n", name,
              e.linear, e.motion, e.motion / e.linear);
  EXPECT_GT(e.linear, 0.0);
  return e;
}

TEST(MotionBlend, TheHalfWayVolumeOfAModelFileIsCloserToTheModelsOwn) {
  // The coarse storm (72 × 64 × 30 at 10 km) converted from its wrfout as `nephele render` does, with
  // U, V the drift its convective cells move with (nephele-gen --steering-wind): the blend of 12 and
  // 14 UTC at w = ½ against the model's 13 UTC, per column optical depth. The cells also grow and
  // decay, the shield stays, the column noise is new every hour: no blend reaches the truth, but the
  // motion blend must come clearly closer than the cross-fade: measured 0.32 of its error (17.3 → 5.6);
  // with the generator's vortex wind, which does not move the cells, 0.92 (and this test would fail).
  const std::string path = (engineTestDir() / "wrfout_storm_steering.nc").string();
  datagen::WrfHurricaneSpec spec = datagen::coarseStormSpec();
  spec.ntimes = 3;
  spec.steering_wind_only = true;
  const HalfWayErrors e = halfWayErrors(spec, path, "storm");
  EXPECT_LT(e.motion, 0.8 * e.linear);
}

// The same against a storm whose wind is sheared with height, as real model winds are: the alpine
// life cycle (nephele-gen wrf --case alpine-storm --times 3; 30 levels instead of 50 for time): the
// towers move with the 0–6 km mean wind (10.5 m/s) while the wind turns from 6 m/s at their bases
// to 24 m/s at their tops, and the towers grow (12 UTC), mature (13) and collapse (14). The blend of
// 12 and 14 UTC at w = ½ against 13 UTC, mean |Δτ| per column: the life cycle puts a floor under
// every blend, and the motion blend, moving each column as one with its cloud-weighted wind, must
// still come closer than the cross-fade (measured: 0.66 of its error; moving each level with its own
// wind, on the 50-level file: 0.58 — it matches the columns' optical depth better while shearing
// the towers into slanted streaks that the frames show, docs/animation.md "Clouds move as
// columns"). Bound 0.9.
TEST(MotionBlend, TheHalfWayVolumeOfAShearedStormIsCloserThanTheCrossFade) {
  const std::string path = (engineTestDir() / "wrfout_alpine_3h.nc").string();
  datagen::WrfHurricaneSpec spec = datagen::alpineStormSpec();
  spec.nz = 30;
  spec.ntimes = 3;
  const HalfWayErrors e = halfWayErrors(spec, path, "alpine");
  EXPECT_LT(e.motion, 0.9 * e.linear);
}

TEST(MotionBlend, TheNphRouteMovesAsTheModelFileDoes) {
  // Issue 13 follow-up: the .nph cache keeps U, V (cache/nph_cache.h), so `nephele convert` then
  // `animate` moves the timesteps as the model file's route does. The coarse storm with the
  // steering wind (nephele-gen wrf --case storm --times 2 --steering-wind), both timesteps
  // converted as `nephele render` does, written with the cache's writer as `nephele convert`
  // writes them, read back, and blended at w = ½ on both routes. They differ by the quantisation
  // only: β by ≤ max/131070 per timestep (quantize.h), U, V by ≤ 0.005 m/s, which moves a
  // trajectory of w·Δt = 30 min by ≤ 9 m, ~1e-3 of a 10-km column. Bound per voxel: the β error,
  // plus, for the trajectory's error, its length in columns times the largest step of β between
  // neighbouring columns (bilinear reads are Lipschitz with it), ×4 for the fixed-point solve's
  // midpoint wind and both axes. Against the cross-fade the .nph route's blend must also stay
  // the motion blend: its column error from the model route's at most 1 % of the cross-fade's.
  const std::string wrf = (engineTestDir() / "wrfout_storm_steering_2.nc").string();
  datagen::WrfHurricaneSpec spec = datagen::coarseStormSpec();
  spec.ntimes = 2;
  spec.steering_wind_only = true;
  datagen::writeWrfHurricane(spec, wrf);
  const auto model = engine::Dataset::open(wrf);
  const ExtinctionVolumes a = model->load(0), b = model->load(1);
  ASSERT_TRUE(engine::blendHasMotion(a, b));
  ASSERT_EQ(a.z_bottom_m, b.z_bottom_m);  // sea level: one grid, as convert's

  const std::filesystem::path nph = engineTestDir() / "storm_steering_2.nph";
  writeNphOf(nph, {a, b});
  const auto cached = engine::Dataset::open(nph.string());
  const ExtinctionVolumes ca = cached->load(0), cb = cached->load(1);
  ASSERT_TRUE(engine::blendHasMotion(ca, cb));

  const ExtinctionVolumes want = engine::blendVolumes(a, b, 0.5, engine::TimeBlend::Motion);
  const ExtinctionVolumes got = engine::blendVolumes(ca, cb, 0.5, engine::TimeBlend::Motion);
  const ExtinctionVolumes fade = engine::blendVolumes(a, b, 0.5, engine::TimeBlend::Linear);
  ASSERT_EQ(got.nx, want.nx);
  ASSERT_EQ(got.ny, want.ny);
  ASSERT_GE(got.nz, want.nz);  // padded to the larger nz_t

  const auto largestStep = [](const ExtinctionVolumes& v, const std::vector<float>& f) {
    double s = 0.0;
    for (int k = 0; k < v.nz; ++k)
      for (int j = 0; j < v.ny; ++j)
        for (int i = 0; i < v.nx; ++i) {
          const double x = f[v.index(i, j, k)];
          if (i + 1 < v.nx) s = std::max(s, std::abs(double(f[v.index(i + 1, j, k)]) - x));
          if (j + 1 < v.ny) s = std::max(s, std::abs(double(f[v.index(i, j + 1, k)]) - x));
        }
    return s;
  };
  const double dt = b.time_utc->secondsSince(*a.time_utc);
  const double columns = cache::kWindErrorBound_m_per_s * 0.5 * dt / std::min(a.georef.dx_m, a.georef.dy_m);
  double worst_ratio = 0.0;
  for (const bool ice : {true, false}) {
    const auto field = [&](const ExtinctionVolumes& v) -> const std::vector<float>& {
      return ice ? v.ice_per_m : v.water_per_m;
    };
    const double max_a = double(ice ? a.max_ice_per_m : a.max_water_per_m);
    const double max_b = double(ice ? b.max_ice_per_m : b.max_water_per_m);
    const double quantised = 0.5 * cache::quantisationErrorBound(max_a) + 0.5 * cache::quantisationErrorBound(max_b);
    const double moved = 4.0 * columns * std::max(largestStep(a, field(a)), largestStep(b, field(b)));
    const double bound = quantised + moved + 0x1p-22 * std::max(max_a, max_b);  // the blend's float sums
    double worst = 0.0;
    for (int k = 0; k < got.nz; ++k)
      for (int j = 0; j < got.ny; ++j)
        for (int i = 0; i < got.nx; ++i) {
          const double w = k < want.nz ? double(field(want)[want.index(i, j, k)]) : 0.0;
          worst = std::max(worst, std::abs(double(field(got)[got.index(i, j, k)]) - w));
        }
    std::printf("[ nph      ] %s: max |nph - model| %.3g /m, bound %.3g (quantisation %.3g, trajectory %.3g)\n",
                ice ? "ice" : "water", worst, bound, quantised, moved);
    EXPECT_LE(worst, bound) << (ice ? "ice" : "water");
    worst_ratio = std::max(worst_ratio, worst / bound);
  }
  // On the model route's own grid, per column optical depth, (the .nph route's padding is zeros.)
  ExtinctionVolumes got_cropped = got;
  got_cropped.nz = want.nz;
  got_cropped.ice_per_m.resize(want.voxelCount());
  got_cropped.water_per_m.resize(want.voxelCount());
  const double nph_error = meanColumnError(got_cropped, want), fade_error = meanColumnError(fade, want);
  std::printf("[ nph      ] mean |tau| per column from the model route's motion blend: .nph %.3g, cross-fade %.3g\n",
              nph_error, fade_error);
  EXPECT_LT(nph_error, 0.01 * fade_error);
}

}  // namespace
}  // namespace nph::test
