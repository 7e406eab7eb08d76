// Ray caster: ms per 1920 × 1080 frame of the realistic generated hurricane (500 × 500 × 60 at
// 3 km, one timestep, height × 8, the `make demo` camera) on this machine's GL, with empty-space
// skipping and early ray termination each on and off, side by side in one run. The deep light map
// is built once (not timed). Time: wall time of CloudRenderer::render incl. read-back.
// Achieved throughput, same run: BM_FetchLimit first measures the foundation's fetch kernel
// (fetch_kernel.h, glsl/bench/fetch3d.comp) on a volume of the hurricane's size and format (R32F,
// trilinear, oblique rays, 1920 × 1080 rays of 128 fetches) — the rate of a ray caster that does
// nothing but sample. Each frame is then rendered once more with sample counting on (untimed),
// and samples_per_s = volume samples of the frame / frame time, fraction_of_fetch_limit =
// samples_per_s / that rate. One sample costs at least two trilinear fetches (ice and water) plus
// the occupancy fetch, and a DLM look-up (four texels, binary search each) where β > 0, so a
// fraction near 1/3 would already mean the ray caster is fetch-bound.
// Run: make bench, or build/tests/bench/nephele_raycast_benchmarks
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include "bench_hurricane.h"
#include "fetch_kernel.h"
#include "render/dlm/deep_light_map.h"
#include "render/gl/context.h"
#include "render/raycast/cloud_renderer.h"
#include "scene/scene_file.h"
#include "scene/sun.h"

namespace {

using namespace nph;

struct Fixture {
  std::unique_ptr<gl::Context> ctx;
  ExtinctionVolumes volumes;
  std::unique_ptr<render::VolumeTextures> textures;
  std::unique_ptr<render::DeepLightMap> dlm;
  std::unique_ptr<render::CloudRenderer> renderer;
  scene::Camera camera;
  scene::Sun sun{140.0, 35.0};
};

Fixture& fixture() {
  static std::unique_ptr<Fixture> f = [] {
    auto fx = std::make_unique<Fixture>();
    fx->ctx = bench::hiddenContext();
    fx->volumes = bench::realisticHurricane("nephele-raycast-bench.nc");
    const auto frame = volume::frameOf(fx->volumes, 8.0);
    fx->textures =
        std::make_unique<render::VolumeTextures>(render::VolumeTextures::upload(fx->volumes, frame, "bench"));
    fx->dlm = std::make_unique<render::DeepLightMap>();
    fx->dlm->build(*fx->textures, -fx->sun.toSun(), lighting::DlmSettings{});
    fx->renderer = std::make_unique<render::CloudRenderer>();
    scene::CameraSpec cs;
    cs.preset = scene::CameraPreset::Oblique;
    cs.fov_deg = 40.0;
    fx->camera = scene::cameraFor(cs, frame, 1920, 1080);
    std::fprintf(stderr, "raycast benchmark: %dx%dx%d voxels on %s\n", fx->volumes.nx, fx->volumes.ny, fx->volumes.nz,
                 fx->ctx->info().renderer.c_str());
    return fx;
  }();
  return *f;
}

double g_fetch_limit_per_s = 0.0;  // BM_FetchLimit's result, for the fractions below

void BM_FetchLimit(benchmark::State& state) {
  Fixture& fx = fixture();
  fx.ctx->makeCurrent();
  const ExtinctionVolumes& v = fx.volumes;
  auto volume = gl::Texture::create3D(GL_R32F, v.nx, v.ny, v.nz).label("fetch-limit volume");
  glTextureSubImage3D(volume.id(), 0, 0, 0, 0, v.nx, v.ny, v.nz, GL_RED, GL_FLOAT, v.water_per_m.data());
  volume.sampling(GL_LINEAR, GL_REPEAT);
  constexpr int kSteps = 128;
  const bench::FetchKernel kernel({1920, 1080}, kSteps);
  const glm::vec3 step = glm::vec3(1.0f / kSteps) * 0.57735f;  // oblique, like the camera's rays
  kernel.dispatch(volume, step);                               // warm-up
  glFinish();
  double seconds = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    kernel.dispatch(volume, step);
    glFinish();
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    state.SetIterationTime(dt);
    seconds += dt;
  }
  g_fetch_limit_per_s = kernel.fetchesPerDispatch() * double(state.iterations()) / seconds;
  state.counters["fetches_per_s"] =
      benchmark::Counter(kernel.fetchesPerDispatch() * double(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel("R32F linear oblique, 1920x1080 rays x 128");
}
BENCHMARK(BM_FetchLimit)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_RaycastFrame(benchmark::State& state) {
  Fixture& fx = fixture();
  fx.ctx->makeCurrent();
  render::RenderSettings rs;
  rs.empty_space_skipping = state.range(0) != 0;
  rs.min_transmittance = state.range(1) != 0 ? 0.01 : 0.0;
  double coverage = 0.0, totalSeconds = 0.0;
  for (auto _ : state) {
    const auto out = fx.renderer->render(*fx.textures, *fx.dlm, fx.camera, fx.sun, rs);
    state.SetIterationTime(out.milliseconds * 1e-3);
    totalSeconds += out.milliseconds * 1e-3;
    coverage = 0.0;
    for (std::size_t i = 3; i < out.cloud_layer.rgba.size(); i += 4) coverage += double(out.cloud_layer.rgba[i]);
    coverage /= double(out.cloud_layer.rgba.size() / 4);
  }
  state.counters["mean_alpha"] = coverage;
  fx.renderer->countSamples(true);  // once more, untimed: how many samples that frame took
  fx.renderer->render(*fx.textures, *fx.dlm, fx.camera, fx.sun, rs);
  const double samples = double(fx.renderer->sampleCount());
  fx.renderer->countSamples(false);
  const double frameSeconds = state.iterations() > 0 ? totalSeconds / double(state.iterations()) : 0.0;
  state.counters["samples"] = samples;
  if (frameSeconds > 0.0) {
    state.counters["samples_per_s"] = samples / frameSeconds;
    if (g_fetch_limit_per_s > 0.0)
      state.counters["fraction_of_fetch_limit"] = samples / frameSeconds / g_fetch_limit_per_s;
  }
  state.SetLabel(std::string(rs.empty_space_skipping ? "skipping" : "no skipping") + ", " +
                 (rs.min_transmittance > 0.0 ? "early termination" : "no early termination"));
}

BENCHMARK(BM_RaycastFrame)
    ->ArgNames({"skip", "early"})
    ->Args({1, 1})
    ->Args({0, 1})
    ->Args({1, 0})
    ->Args({0, 0})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
