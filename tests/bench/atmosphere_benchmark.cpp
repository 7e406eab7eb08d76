// The atmosphere's cost (issue 14 item 3): the start-up tables (transmittance, Ψ_ms, sky
// irradiance; render/atmosphere/atmosphere_luts.h), a sky-view rebuild (once per frame where the
// camera's altitude or the sun moved), and a whole 1280 × 720 frame of the realistic generated
// hurricane with the atmosphere on and off (the flat `make demo` camera), interleaved
// (off, on, off, on, …, 7 pairs) so that load on this shared machine hits both alike; medians and
// the on/off ratio are reported as counters. Wall time incl. glFinish / read-back.
// Run: make bench, or build/tests/bench/nephele_atmosphere_benchmarks
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <vector>

#include "bench_hurricane.h"
#include "bench_stats.h"
#include "render/atmosphere/atmosphere_luts.h"
#include "render/dlm/deep_light_map.h"
#include "render/gl/context.h"
#include "render/raycast/cloud_renderer.h"
#include "scene/scene_file.h"
#include "scene/sun.h"

namespace {

using namespace nph;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

using bench::median;

struct Fixture {
  std::unique_ptr<gl::Context> ctx;
  ExtinctionVolumes volumes;
  volume::VolumeFrame frame;
  std::unique_ptr<render::VolumeTextures> textures;
  std::unique_ptr<render::DeepLightMap> dlm;
  scene::Camera camera;
  scene::Sun sun{140.0, 35.0};
};

Fixture& fixture() {
  static std::unique_ptr<Fixture> f = [] {
    auto fx = std::make_unique<Fixture>();
    fx->ctx = bench::hiddenContext();
    fx->volumes = bench::realisticHurricane("nephele-atmosphere-bench.nc");
    fx->frame = volume::frameOf(fx->volumes, 8.0);
    fx->textures =
        std::make_unique<render::VolumeTextures>(render::VolumeTextures::upload(fx->volumes, fx->frame, "bench"));
    fx->dlm = std::make_unique<render::DeepLightMap>();
    fx->dlm->build(*fx->textures, -fx->sun.toSun(), lighting::DlmSettings{});
    scene::CameraSpec cs;
    cs.preset = scene::CameraPreset::Oblique;
    cs.fov_deg = 40.0;
    fx->camera = scene::cameraFor(cs, fx->frame, 1280, 720);
    std::fprintf(stderr, "atmosphere benchmark: %dx%dx%d voxels on %s\n", fx->volumes.nx, fx->volumes.ny,
                 fx->volumes.nz, fx->ctx->info().renderer.c_str());
    return fx;
  }();
  return *f;
}

// Start-up tables (5 builds) and the sky-view table (9 rebuilds, the sun moving 1° each time).
void BM_AtmosphereTables(benchmark::State& state) {
  fixture();
  std::vector<double> build, view;
  for (auto _ : state) {
    for (int i = 0; i < 5; ++i) {
      render::AtmosphereLuts luts;
      build.push_back(luts.buildMilliseconds());
      if (i == 0) {
        for (int k = 0; k < 9; ++k) {
          const double e = glm::radians(20.0 + k);
          luts.updateSkyView(1000.0, {std::cos(e), 0.0, std::sin(e)});
          glFinish();
          const auto t0 = Clock::now();
          luts.updateSkyView(1000.0, {std::cos(e + 0.5), 0.0, std::sin(e + 0.5)});
          glFinish();
          view.push_back(msSince(t0));
        }
      }
    }
  }
  state.counters["tables_ms_median"] = median(build);
  state.counters["sky_view_ms_median"] = median(view);
}
BENCHMARK(BM_AtmosphereTables)->Iterations(1)->Unit(benchmark::kMillisecond);

// One flat-view frame with the atmosphere off and on, interleaved.
void BM_AtmosphereFrame(benchmark::State& state) {
  Fixture& fx = fixture();
  render::CloudRenderer renderer;
  const scene::Camera& camera = fx.camera;
  render::RenderSettings off, on;
  off.atmosphere = false;
  on.atmosphere = true;
  renderer.render(*fx.textures, *fx.dlm, camera, fx.sun, on);  // builds the tables, warms both paths
  renderer.render(*fx.textures, *fx.dlm, camera, fx.sun, off);
  std::vector<double> offMs, onMs;
  for (auto _ : state) {
    for (int i = 0; i < 7; ++i) {
      offMs.push_back(renderer.render(*fx.textures, *fx.dlm, camera, fx.sun, off).milliseconds);
      onMs.push_back(renderer.render(*fx.textures, *fx.dlm, camera, fx.sun, on).milliseconds);
    }
  }
  state.counters["off_ms_median"] = median(offMs);
  state.counters["on_ms_median"] = median(onMs);
  state.counters["on_over_off"] = median(onMs) / median(offMs);
}
BENCHMARK(BM_AtmosphereFrame)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
