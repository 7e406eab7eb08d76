// The CPU cost of a volume between two timesteps (engine::blendVolumes; docs/animation.md "Between
// two timesteps"): the cross-fade against the motion-compensated blend (semi-Lagrangian
// trajectories with each timestep's U, V, then bilinear reads; engine/dataset.h TimeBlend), on a
// grid of the demo storm's size (the realistic generated hurricane of `make demo`, 500 × 500 × 64
// at 3 km) with everything a model file carries: ice, water and the five detail fields (TKE, cloud
// fraction, W, U, V). The cost does not depend on the values (no branch on them), so the fields
// are synthetic: a smooth pattern of cells and a rotating wind of up to 30 m/s, hourly timesteps.
// Interleave the variants against drifting machine load and report medians:
//   build/tests/bench/nephele_blend_benchmarks --benchmark_enable_random_interleaving=true
//       --benchmark_repetitions=5 --benchmark_report_aggregates_only=true   (one line)
// NEPHELE_BENCH_SIZE=tiny: 100 × 100 × 16 (seconds).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "engine/dataset.h"
#include "geo/utc_time.h"

namespace {

using namespace nph;

ExtinctionVolumes timestep(int n, int nz, double hours) {
  ExtinctionVolumes v = ExtinctionVolumes::zeros(n, n, nz, 3000.0, 250.0, 0.0);
  v.time_utc = geo::UtcTime::parse("2026-09-01T12:00:00Z").plusSeconds(3600.0 * hours);
  for (auto* f : {&v.tke_m2_per_s2, &v.cloud_fraction, &v.wind_w_m_per_s, &v.wind_u_m_per_s, &v.wind_v_m_per_s})
    f->assign(v.voxelCount(), 0.0f);
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const std::size_t c = v.index(i, j, k);
        const double x = double(i) / n - 0.5, y = double(j) / n - 0.5;
        const double cells = std::max(0.0, std::sin(40.0 * x + hours) * std::sin(37.0 * y) - 0.3);
        v.ice_per_m[c] = float(0.01 * cells * (k > nz / 2));
        v.water_per_m[c] = float(0.02 * cells * (k <= nz / 2));
        v.tke_m2_per_s2[c] = float(cells);
        v.cloud_fraction[c] = float(std::min(1.0, 3.0 * cells));
        v.wind_w_m_per_s[c] = float(cells);
        v.wind_u_m_per_s[c] = float(-60.0 * y);  // solid rotation, 30 m/s at the edges
        v.wind_v_m_per_s[c] = float(60.0 * x);
      }
    }
  }
  v.updateMaxima();
  return v;
}

struct Pair {
  ExtinctionVolumes a, b;
};

const Pair& pair() {
  static const Pair p = [] {
    const char* size = std::getenv("NEPHELE_BENCH_SIZE");
    const bool tiny = size && std::string(size) == "tiny";
    const int n = tiny ? 100 : 500, nz = tiny ? 16 : 64;
    return Pair{timestep(n, nz, 0.0), timestep(n, nz, 1.0)};
  }();
  return p;
}

// `threads`: 0 = TBB's default (every core), 1 = the serial blend of before.
void BM_Blend(benchmark::State& state, engine::TimeBlend blend, int threads) {
  const Pair& p = pair();
  const tbb::global_control limit(
      tbb::global_control::max_allowed_parallelism,
      threads > 0 ? std::size_t(threads)
                  : tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  double w = 0.3;
  for (auto _ : state) {
    ExtinctionVolumes m = engine::blendVolumes(p.a, p.b, w, blend);
    benchmark::DoNotOptimize(m.ice_per_m.data());
    w = w == 0.3 ? 0.7 : 0.3;
  }
  state.counters["voxels"] = double(p.a.voxelCount());
  state.counters["motion"] = engine::blendHasMotion(p.a, p.b) && blend == engine::TimeBlend::Motion ? 1.0 : 0.0;
}

// Wall time (UseRealTime) next to the process CPU time: the motion blend runs its levels on TBB.
BENCHMARK_CAPTURE(BM_Blend, linear, engine::TimeBlend::Linear, 0)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Blend, motion, engine::TimeBlend::Motion, 0)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Blend, motion_one_thread, engine::TimeBlend::Motion, 1)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
