// Ray caster: ms per 1920 × 1080 frame of the realistic generated hurricane (500 × 500 × 60 at
// 3 km, one timestep, height × 8, the `make demo` camera) on this machine's GL, with empty-space
// skipping and early ray termination each on and off, side by side in one run. The deep light map
// is built once (not timed). Time: wall time of CloudRenderer::render incl. read-back.
// Run: make bench, or build/tests/bench/nephele_raycast_benchmarks
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <memory>

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
    gl::ContextOptions o;
    o.backend = gl::backendFromEnvironment();
    o.visible = false;
    fx->ctx = gl::createContext(o);
    datagen::WrfHurricaneSpec spec = datagen::wrfPreset(datagen::SampleSize::Realistic);
    spec.ntimes = 1;
    spec.format = datagen::NcFormat::Classic64;
    const auto path = (std::filesystem::temp_directory_path() / "nephele-raycast-bench.nc").string();
    datagen::writeWrfHurricane(spec, path);
    const auto file = io::openModelFile(path);
    fx->volumes = physics::buildExtinctionVolumes(file.load(0), physics::defaultOptics(), physics::VerticalGridOptions{});
    std::filesystem::remove(path);
    const auto frame = scene::frameOf(fx->volumes, 8.0);
    fx->textures = std::make_unique<render::VolumeTextures>(render::VolumeTextures::upload(fx->volumes, frame, "bench"));
    fx->dlm = std::make_unique<render::DeepLightMap>();
    fx->dlm->build(*fx->textures, -fx->sun.toSun(), scene::DlmSettings{});
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

void BM_RaycastFrame(benchmark::State& state) {
  Fixture& fx = fixture();
  fx.ctx->makeCurrent();
  render::RenderSettings rs;
  rs.empty_space_skipping = state.range(0) != 0;
  rs.min_transmittance = state.range(1) != 0 ? 0.01 : 0.0;
  double coverage = 0.0;
  for (auto _ : state) {
    const auto out = fx.renderer->render(*fx.textures, *fx.dlm, fx.camera, fx.sun, rs);
    state.SetIterationTime(out.milliseconds * 1e-3);
    coverage = 0.0;
    for (std::size_t i = 3; i < out.cloud_layer.rgba.size(); i += 4) coverage += double(out.cloud_layer.rgba[i]);
    coverage /= double(out.cloud_layer.rgba.size() / 4);
  }
  state.counters["mean_alpha"] = coverage;
  state.SetLabel(std::string(rs.empty_space_skipping ? "skipping" : "no skipping") + ", " +
                 (rs.min_transmittance > 0.0 ? "early termination" : "no early termination"));
}

BENCHMARK(BM_RaycastFrame)
    ->ArgNames({"skip", "early"})
    ->Args({1, 1})->Args({0, 1})->Args({1, 0})->Args({0, 0})
    ->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
