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
#include <cmath>
#include <cstdio>
#include <memory>
#include <utility>
#include <vector>

#include "bench_hurricane.h"
#include "bench_stats.h"
#include "render/dlm/deep_light_map.h"
#include "render/raycast/cloud_renderer.h"
#include "scene/scene_setup.h"
#include "scene/sun.h"
#include "volume/terrain_field.h"

namespace {

using namespace nph;

using bench::median;

/// Issue 13's coarse storm with the mountain of `make demo`'s terrain shot before session 16 (tools/demo.sh now
/// renders `nephele-gen wrf --case alpine-storm`).
ExtinctionVolumes stormOverMountain(const char* file) {
  datagen::WrfHurricaneSpec spec = datagen::coarseStormSpec();
  spec.ntimes = 1;
  spec.centre_lon_deg = 11.85;  // tools/demo.sh: the domain over the Alps, the mountain on the Bernese Alps
  spec.centre_lat_deg = 47.1;
  spec.mountain = {8.0, 46.5, 3000.0, 35000.0};
  return bench::generatedVolumes(spec, file);
}

/// The demo's camera: low, from the west across the mountain towards the storm.
scene::Camera demoCamera() {
  scene::Camera camera;
  camera.width = 640;
  camera.height = 360;
  camera.vertical_fov_deg = 40.0;
  camera.position_m = {-90000.0, 160000.0, 24000.0};
  camera.target_m = {220000.0, 320000.0, 2000.0};
  return camera;
}

/// Frame times [ms] of `a` and `b` (each renders one frame), one warm-up each, then 5 interleaved
/// pairs: the medians.
template <class A, class B>
std::pair<double, double> interleavedMedians(benchmark::State& state, A a, B b) {
  (void)a();  // atmosphere tables, warm both paths
  (void)b();
  std::vector<double> aMs, bMs;
  for (auto _ : state) {
    for (int i = 0; i < 5; ++i) {
      aMs.push_back(a());
      bMs.push_back(b());
    }
  }
  return {median(aMs), median(bMs)};
}

void BM_TerrainFrame(benchmark::State& state) {
  auto ctx = bench::hiddenContext();
  const ExtinctionVolumes volumes = stormOverMountain("nephele-terrain-bench.nc");
  const volume::VolumeFrame frame = volume::frameOf(volumes, 4.0);
  const auto textures = render::VolumeTextures::upload(volumes, frame, "bench");
  const scene::Sun sun{215.0, 6.0};
  render::DeepLightMap dlm;
  dlm.build(textures, -sun.toSun(), lighting::DlmSettings{});
  const scene::Camera camera = demoCamera();
  std::fprintf(stderr, "terrain benchmark: %dx%dx%d voxels, terrain max %.0f m (world) on %s\n", volumes.nx, volumes.ny,
               volumes.nz, textures.terrain().max_m, ctx->info().renderer.c_str());
  render::CloudRenderer renderer;
  render::RenderSettings off, on;
  off.terrain = false;
  on.terrain = true;
  const auto [offMs, onMs] = interleavedMedians(
      state, [&] { return renderer.render(textures, dlm, camera, sun, off).milliseconds; },
      [&] { return renderer.render(textures, dlm, camera, sun, on).milliseconds; });
  state.counters["off_ms_median"] = offMs;
  state.counters["on_ms_median"] = onMs;
  state.counters["on_over_off"] = onMs / offMs;
}
BENCHMARK(BM_TerrainFrame)->Iterations(1)->Unit(benchmark::kMillisecond);

// A user DEM's far field (scene/dem.h; docs/terrain.md "A user DEM"): the same frame and camera,
// terrain on, with the volume uploaded without and with a far field over the far basemap's square
// (1024² pixels, made in memory: a 2500 m ridge, σ = 25 km across, running north-south 180 km
// beyond the grid's east edge, in the camera's line of sight), interleaved, 5 pairs. The march then
// crosses the far square wherever a ray is within the terrain's height slab.
void BM_DemFarFieldFrame(benchmark::State& state) {
  auto ctx = bench::hiddenContext();
  const ExtinctionVolumes volumes = stormOverMountain("nephele-dem-bench.nc");
  const volume::VolumeFrame frame = volume::frameOf(volumes, 4.0);
  volume::DemHeights dem;
  dem.source = "<generated ridge>";
  const scene::WorldRect far = scene::farBasemapRectangle(frame);
  dem.far_size = glm::ivec2(scene::kFarBasemapPixels);
  dem.far_min_m = far.min_m;
  dem.far_max_m = far.max_m;
  dem.far_m.resize(std::size_t(dem.far_size.x) * std::size_t(dem.far_size.y));
  const glm::dvec2 cell = (far.max_m - far.min_m) / glm::dvec2(dem.far_size);
  const double ridgeX_m = frame.size_m().x + 180000.0, sigma_m = 25000.0;
  for (int j = 0; j < dem.far_size.y; ++j) {
    for (int i = 0; i < dem.far_size.x; ++i) {
      const double dx = far.min_m.x + (i + 0.5) * cell.x - ridgeX_m;
      dem.far_m[std::size_t(j) * std::size_t(dem.far_size.x) + std::size_t(i)] =
          float(2500.0 * std::exp(-dx * dx / (2.0 * sigma_m * sigma_m)));
    }
  }
  const auto without = render::VolumeTextures::upload(volumes, frame, "bench");
  const auto with = render::VolumeTextures::upload(volumes, frame, "bench", {.dem = &dem});
  const scene::Sun sun{215.0, 6.0};
  render::DeepLightMap dlm;
  dlm.build(without, -sun.toSun(), lighting::DlmSettings{});  // the DLM does not read the terrain
  const scene::Camera camera = demoCamera();
  render::CloudRenderer renderer;
  render::RenderSettings on;
  on.terrain = true;
  const auto [withoutMs, withMs] = interleavedMedians(
      state, [&] { return renderer.render(without, dlm, camera, sun, on).milliseconds; },
      [&] { return renderer.render(with, dlm, camera, sun, on).milliseconds; });
  state.counters["model_terrain_ms_median"] = withoutMs;
  state.counters["with_far_dem_ms_median"] = withMs;
  state.counters["far_dem_over_model"] = withMs / withoutMs;
}
BENCHMARK(BM_DemFarFieldFrame)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
