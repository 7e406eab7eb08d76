// The terrain's cost (issue 14 item 2): a whole 640 × 360 flat-view frame of the storm over the
// mountain — issue 13's coarse storm (72 × 64 columns at 10 km) with the 3000 m Gaussian mountain
// of `make demo` in HGT, height × 4, the demo's low golden-hour camera (sun 6° high) — with the
// terrain off (the plane z = 0) and on (the march of glsl/common/terrain.glsl for every eye ray
// into the height slab, the normal, and the terrain's shadow ray from every sunlit ground pixel),
// interleaved (off, on, …, 5 pairs) so that load on this shared machine hits both alike; medians
// and the on/off ratio are reported as counters. Wall time of CloudRenderer::render incl. read-back.
// Run: make bench, or build/tests/bench/nephele_terrain_benchmarks
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <vector>

#include "bench_hurricane.h"
#include "bench_stats.h"
#include "render/dlm/deep_light_map.h"
#include "render/raycast/cloud_renderer.h"
#include "scene/sun.h"

namespace {

using namespace nph;

using bench::median;

void BM_TerrainFrame(benchmark::State& state) {
  auto ctx = bench::hiddenContext();
  datagen::WrfHurricaneSpec spec = datagen::coarseStormSpec();
  spec.ntimes = 1;
  spec.mountain = {-77.9, 24.4, 3000.0, 35000.0};  // examples/scenes/demo-terrain.json.in's data
  const ExtinctionVolumes volumes = bench::generatedVolumes(spec, "nephele-terrain-bench.nc");
  const scene::VolumeFrame frame = scene::frameOf(volumes, 4.0);
  const auto textures = render::VolumeTextures::upload(volumes, frame, "bench");
  const scene::Sun sun{215.0, 6.0};
  render::DeepLightMap dlm;
  dlm.build(textures, -sun.toSun(), scene::DlmSettings{});
  // The demo's camera: low, from the west across the mountain towards the storm.
  scene::Camera camera;
  camera.width = 640;
  camera.height = 360;
  camera.vertical_fov_deg = 40.0;
  camera.position_m = {-90000.0, 160000.0, 24000.0};
  camera.target_m = {220000.0, 320000.0, 2000.0};
  std::fprintf(stderr, "terrain benchmark: %dx%dx%d voxels, terrain max %.0f m (world) on %s\n", volumes.nx, volumes.ny,
               volumes.nz, textures.terrain().max_m, ctx->info().renderer.c_str());
  render::CloudRenderer renderer;
  render::RenderSettings off, on;
  off.terrain = false;
  on.terrain = true;
  renderer.render(textures, dlm, camera, sun, on);  // atmosphere tables, warm both paths
  renderer.render(textures, dlm, camera, sun, off);
  std::vector<double> offMs, onMs;
  for (auto _ : state) {
    for (int i = 0; i < 5; ++i) {
      offMs.push_back(renderer.render(textures, dlm, camera, sun, off).milliseconds);
      onMs.push_back(renderer.render(textures, dlm, camera, sun, on).milliseconds);
    }
  }
  state.counters["off_ms_median"] = median(offMs);
  state.counters["on_ms_median"] = median(onMs);
  state.counters["on_over_off"] = median(onMs) / median(offMs);
}
BENCHMARK(BM_TerrainFrame)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
