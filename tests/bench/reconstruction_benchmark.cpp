// Cost of the extinction filter (issue 13; volume/reconstruction.h): trilinear against the cubic
// B-spline (8 trilinear fetches per phase and sample, Sigg & Hadwiger 2005), on the coarse storm
// (datagen::coarseStormSpec, 72×64 columns at 10 km, 30 levels → 250 m output levels) at the demo's
// view (oblique preset, 40°, sun 140°/35°, heights × 8), 1920 × 1080. One benchmark iteration
// renders both filters back to back — DLM build (all three passes) and ray cast — so the two are
// interleaved and share the machine's load; the counters are the medians over the iterations and
// their ratios (cubic / trilinear). Wall times include the read-back (CloudRenderer) and glFinish.
// Run: build/tests/bench/nephele_reconstruction_benchmarks (part of make bench).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "bench_hurricane.h"
#include "bench_stats.h"
#include "io/model_file.h"
#include "physics/volume_builder.h"
#include "presets.h"
#include "render/dlm/deep_light_map.h"
#include "render/gl/context.h"
#include "render/raycast/cloud_renderer.h"
#include "scene/scene_file.h"
#include "scene/sun.h"

namespace {

using namespace nph;

using bench::median;

void BM_ReconstructionCost(benchmark::State& state) {
  gl::ContextOptions o;
  o.backend = gl::backendFromEnvironment();
  o.visible = false;
  const auto ctx = gl::createContext(o);
  datagen::WrfHurricaneSpec spec = datagen::coarseStormSpec();
  spec.ntimes = 1;
  const ExtinctionVolumes v = bench::generatedVolumes(spec, "nephele-reconstruction-bench.nc");
  const auto frame = volume::frameOf(v, 8.0);
  const scene::Sun sun{140.0, 35.0};
  scene::CameraSpec cs;
  cs.preset = scene::CameraPreset::Oblique;
  cs.fov_deg = 40.0;
  const scene::Camera camera = scene::cameraFor(cs, frame, 1920, 1080);
  const render::VolumeTextures tex[2] = {
      render::VolumeTextures::upload(v, frame, "bench", {.reconstruction = volume::Reconstruction::Trilinear}),
      render::VolumeTextures::upload(v, frame, "bench", {.reconstruction = volume::Reconstruction::Cubic})};
  render::CloudRenderer renderer;
  render::RenderSettings rs;
  std::vector<double> dlm_ms[2], ray_ms[2];
  for (auto _ : state) {
    double total = 0.0;
    for (int r = 0; r < 2; ++r) {
      render::DeepLightMap dlm;  // a fresh map each time: the cache key would skip the build
      const auto t0 = std::chrono::steady_clock::now();
      dlm.build(tex[r], -sun.toSun(), lighting::DlmSettings{});
      glFinish();
      dlm_ms[r].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      ray_ms[r].push_back(renderer.render(tex[r], dlm, camera, sun, rs).milliseconds);
      total += dlm_ms[r].back() + ray_ms[r].back();
    }
    state.SetIterationTime(total * 1e-3);
  }
  state.counters["dlm_ms_trilinear"] = median(dlm_ms[0]);
  state.counters["dlm_ms_cubic"] = median(dlm_ms[1]);
  state.counters["dlm_ratio"] = median(dlm_ms[1]) / median(dlm_ms[0]);
  state.counters["raycast_ms_trilinear"] = median(ray_ms[0]);
  state.counters["raycast_ms_cubic"] = median(ray_ms[1]);
  state.counters["raycast_ratio"] = median(ray_ms[1]) / median(ray_ms[0]);
  std::fprintf(stderr, "reconstruction benchmark: %dx%dx%d voxels on %s\n", v.nx, v.ny, v.nz,
               ctx->info().renderer.c_str());
}
BENCHMARK(BM_ReconstructionCost)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(5);

}  // namespace

BENCHMARK_MAIN();
