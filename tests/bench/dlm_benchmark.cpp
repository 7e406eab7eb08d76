// Deep light map: build time against error for every quality knob, side by side in one run
// (these machines are noisy: compare medians and ratios). Scene: a generated hurricane of
// 80 × 80 × 20 model points at 15 km (1200 km wide), one timestep, sun at 45° elevation.
// Error: max and mean |I − I_best| of the CPU look-up (the GPU's rules) at 20 000 random points in
// the cloud's bounding box, against a map built with the tightest settings (ε = 1e-4, Δ = ⅛ voxel,
// texel = ½ voxel). Time: wall time of DeepLightMap::build incl. glFinish and the read-backs of
// the overflow rule and stats (manual time).
// BM_RadianceVolumeBuild (issue 12, seventeenth session): the Monte Carlo radiance volume's build
// (render/dlm/radiance_volume.h) on the accuracy hurricane from above, the tally summed per run of
// crossings in one cell against one SSBO addition per crossing (the sixteenth session's), interleaved.
// Run: make bench, or build/tests/bench/nephele_dlm_benchmarks
#include <benchmark/benchmark.h>

#include <fmt/format.h>
#include "bench_stats.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "io/model_file.h"
#include "physics/volume_builder.h"
#include "presets.h"
#include "render/dlm/deep_light_map.h"
#include "render/dlm/radiance_volume.h"
#include "render/gl/context.h"
#include "scene/sun.h"

namespace {

using namespace nph;

struct Fixture {
  std::unique_ptr<gl::Context> ctx;
  ExtinctionVolumes volumes;
  std::unique_ptr<render::VolumeTextures> textures;
  glm::dvec3 light;
  std::vector<glm::dvec3> points;
  render::DeepLightMap::Readback bestMap;
  lighting::LightSpace bestSpace;
};

Fixture& fixture() {
  static std::unique_ptr<Fixture> f = [] {
    auto fx = std::make_unique<Fixture>();
    gl::ContextOptions o;
    o.backend = gl::backendFromEnvironment();
    o.visible = false;
    fx->ctx = gl::createContext(o);
    datagen::WrfHurricaneSpec spec;
    spec.nx = 80;
    spec.ny = 80;
    spec.ntimes = 1;
    const auto path = (std::filesystem::temp_directory_path() / "nephele-dlm-bench.nc").string();
    datagen::writeWrfHurricane(spec, path);
    const auto file = io::openModelFile(path);
    fx->volumes =
        physics::buildExtinctionVolumes(file.load(0), physics::defaultOptics(), physics::VerticalGridOptions{});
    std::filesystem::remove(path);
    const auto frame = volume::frameOf(fx->volumes);
    fx->textures =
        std::make_unique<render::VolumeTextures>(render::VolumeTextures::upload(fx->volumes, frame, "bench"));
    fx->light = -scene::Sun{135.0, 45.0}.toSun();
    glm::dvec3 lo, hi;
    fx->textures->nonEmptyBox(lo, hi);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 20000; ++i) fx->points.push_back(lo + (hi - lo) * glm::dvec3(u(rng), u(rng), u(rng)));
    lighting::DlmSettings best;
    best.epsilon = 1e-4;
    best.step_voxels = 0.125;
    best.texel_voxels = 0.5;
    best.max_nodes = 256;
    best.scatter_slice_cells = 0.0;  // the finest slices (4 steps)
    render::DeepLightMap dlm;
    dlm.build(*fx->textures, fx->light, best);
    fx->bestMap = dlm.readBack();
    fx->bestSpace = dlm.lightSpace();
    std::fprintf(stderr, "dlm benchmark: %dx%dx%d voxels, %s; best map %dx%d texels, %d steps\n", fx->volumes.nx,
                 fx->volumes.ny, fx->volumes.nz, fx->ctx->info().renderer.c_str(), dlm.lightSpace().texels.x,
                 dlm.lightSpace().texels.y, dlm.stats().steps);
    return fx;
  }();
  return *f;
}

enum Knob { Baseline, Epsilon, Texel, Step, NoSkip, NoScatter, ScatterCoarse, Nodes, ScatterSlices, SliceCells };

void BM_DlmBuild(benchmark::State& state) {
  Fixture& fx = fixture();
  fx.ctx->makeCurrent();
  lighting::DlmSettings s;
  const auto knob = static_cast<Knob>(state.range(0));
  const double value = double(state.range(1)) / 1000.0;
  switch (knob) {
    case Baseline: break;
    case Epsilon: s.epsilon = value; break;
    case Texel: s.texel_voxels = value; break;
    case Step: s.step_voxels = value; break;
    case NoSkip: s.empty_space_skipping = false; break;
    case NoScatter: s.peripheral = false; break;
    case ScatterCoarse: s.scatter_downsample = int(value); break;
    case Nodes: s.max_nodes = int(value); break;
    case ScatterSlices:  // the steps alone (scatter_slice_cells off)
      s.scatter_slice_steps = int(value);
      s.scatter_slice_cells = 0.0;
      break;
    case SliceCells: s.scatter_slice_cells = value; break;
  }
  render::DeepLightMap dlm;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    dlm.build(*fx.textures, fx.light, s);
    const auto t1 = std::chrono::steady_clock::now();
    state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
    // Force a rebuild next iteration: change the key without changing the map.
    s.max_texels = s.max_texels == 1024 ? 1025 : 1024;
  }
  const auto map = dlm.readBack();
  double maxErr = 0.0, sumErr = 0.0;
  for (const auto& p : fx.points) {
    const double e = std::abs(render::DeepLightMap::lookup(map, dlm.lightSpace(), p) -
                              render::DeepLightMap::lookup(fx.bestMap, fx.bestSpace, p));
    maxErr = std::max(maxErr, e);
    sumErr += e;
  }
  const auto& st = dlm.stats();
  state.counters["max_err"] = maxErr;
  state.counters["mean_err"] = sumErr / double(fx.points.size());
  state.counters["pass1_ms"] = st.pass1_ms;
  state.counters["pass2_ms"] = st.pass2_ms;
  state.counters["pass3_ms"] = st.pass3_ms;
  state.counters["nodes_mean"] = st.mean_nodes;
  state.counters["nodes_max"] = st.max_nodes_used;
  state.counters["MB"] = double(st.bytes) / 1e6;
  state.counters["scatter_slices"] = st.scatter_cells.z;
  state.counters["compression"] = st.compression_ratio;
  state.counters["unbounded"] = st.unbounded_texels;
  static const char* names[] = {
      "baseline",           "epsilon",   "texel_voxels",        "step_voxels",        "no_skipping", "no_scatter_map",
      "scatter_downsample", "max_nodes", "scatter_slice_steps", "scatter_slice_cells"};
  state.SetLabel(knob == Baseline || knob == NoSkip || knob == NoScatter ? names[knob]
                                                                         : fmt::format("{}={:g}", names[knob], value));
}

BENCHMARK(BM_DlmBuild)
    ->ArgNames({"knob", "value_x1000"})
    ->Args({Baseline, 0})
    ->Args({Epsilon, 2})
    ->Args({Epsilon, 5})
    ->Args({Epsilon, 20})
    ->Args({Epsilon, 50})
    ->Args({Texel, 500})
    ->Args({Texel, 2000})
    ->Args({Step, 250})
    ->Args({Step, 1000})
    ->Args({NoSkip, 0})
    ->Args({NoScatter, 0})
    ->Args({ScatterCoarse, 2000})
    ->Args({ScatterCoarse, 8000})
    ->Args({Nodes, 8000})
    ->Args({ScatterSlices, 16000})
    ->Args({ScatterSlices, 64000})
    ->Args({ScatterSlices, 256000})
    ->Args({SliceCells, 0})
    ->Args({SliceCells, 125})
    ->Args({SliceCells, 250})
    ->Args({SliceCells, 1000})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// The per-frame path's build without the statistics read back (issue 19 item 2;
// DeepLightMap::setStatsReadBack(false): overflow retries dispatched indirectly, no pass timed,
// no counts read) against the default build, interleaved in one run with the order alternating,
// each timed to a glFinish so both are "the map is ready". Medians of the rounds and their ratio
// (off / on). Arg: ε in 1e-6 (the default 5e-3 overflows nothing; 1e-4 makes the retries work).
void BM_DlmStatsReadBack(benchmark::State& state) {
  Fixture& fx = fixture();
  fx.ctx->makeCurrent();
  lighting::DlmSettings s;
  s.epsilon = double(state.range(0)) * 1e-6;
  render::DeepLightMap on, off;
  off.setStatsReadBack(false);
  std::vector<double> tOn, tOff;
  int round = 0;
  for (auto _ : state) {
    double roundMs = 0.0;
    for (int i = 0; i < 2; ++i) {
      const bool readBack = (i + round) % 2 == 0;
      render::DeepLightMap& dlm = readBack ? on : off;
      s.max_texels = s.max_texels == 1024 ? 1025 : 1024;  // a new key, the same map: a rebuild
      glFinish();
      const auto t0 = std::chrono::steady_clock::now();
      dlm.build(*fx.textures, fx.light, s);
      glFinish();
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      (readBack ? tOn : tOff).push_back(ms);
      roundMs += ms;
    }
    state.SetIterationTime(roundMs / 1000.0);
    ++round;
  }
  state.counters["read_back_ms"] = bench::median(tOn);
  state.counters["no_read_back_ms"] = bench::median(tOff);
  state.counters["ratio"] = bench::median(tOff) / std::max(bench::median(tOn), 1e-9);
  state.counters["read_backs_in_build"] =
      double(on.stats().build_read_backs) / double(std::max<std::size_t>(1, tOn.size()));
  state.counters["overflowed_texels"] = on.stats().overflowed_texels;
  state.counters["same_histogram"] = on.stats().node_histogram == off.stats().node_histogram ? 1.0 : 0.0;
}
BENCHMARK(BM_DlmStatsReadBack)
    ->ArgNames({"eps_x1e6"})
    ->Args({5000})
    ->Args({100})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(7);

// Pass 1 against a plain fixed-step light volume of the same light space and step: every sample
// stored (no compression, no empty-space skipping), as a non-DLM renderer would precompute it.
void BM_Pass1VersusUncompressedLightVolume(benchmark::State& state) {
  Fixture& fx = fixture();
  fx.ctx->makeCurrent();
  lighting::DlmSettings s;
  s.peripheral = false;
  render::DeepLightMap dlm;
  double pass1 = 0.0, plain = 0.0;
  std::size_t plainBytes = 0;
  for (auto _ : state) {
    dlm.build(*fx.textures, fx.light, s);
    pass1 += dlm.stats().pass1_ms;
    plain += dlm.timeUncompressedLightVolume(*fx.textures, plainBytes);
    state.SetIterationTime(dlm.stats().pass1_ms * 1e-3);
    s.max_texels = s.max_texels == 1024 ? 1025 : 1024;  // force the rebuild
  }
  const double it = double(state.iterations());
  state.counters["pass1_ms"] = pass1 / it;
  state.counters["uncompressed_ms"] = plain / it;
  state.counters["speedup"] = plain / pass1;
  state.counters["dlm_MB"] = double(dlm.stats().bytes) / 1e6;
  state.counters["uncompressed_MB"] = double(plainBytes) / 1e6;
}
BENCHMARK(BM_Pass1VersusUncompressedLightVolume)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(3);

// The radiance volume's build, three ways in rotating order each round, on the accuracy sweep's
// hurricane (96 × 96 model points at 7 km, × 8, sun 120°/70°: hurricane-above-sun-high,
// src/accuracy/accuracy_scenes.cpp), `photons` per build: the GPU port with its tally per run of
// crossings in one cell (the default), the GPU port with one SSBO addition of every moment per
// crossing (RadianceVolume(true), the sixteenth session's; the same sums bit for bit,
// tests/render/radiance_volume_gl_test.cpp), and the CPU twin uploaded into the same textures
// (RadianceVolumeBackend::Cpu, thirty-first session: Auto's choice on a software rasteriser; its
// time includes reading β back from the textures and the upload). Reported: median wall ms incl.
// glFinish of each, the ratios against the GPU runs (> 1: the runs are faster), collisions per
// photon and the resumable build's dispatches.
void BM_RadianceVolumeBuild(benchmark::State& state) {
  const std::uint32_t photons = std::uint32_t(state.range(0));
  gl::ContextOptions o;
  o.backend = gl::backendFromEnvironment();
  o.visible = false;
  const auto ctx = gl::createContext(o);
  datagen::WrfHurricaneSpec spec = datagen::wrfPreset(datagen::SampleSize::Tiny);
  spec.nx = 96;
  spec.ny = 96;
  spec.nz = 30;
  spec.dx_m = 7000.0;
  spec.ntimes = 1;
  const auto path = (std::filesystem::temp_directory_path() / "nephele-rv-bench.nc").string();
  datagen::writeWrfHurricane(spec, path);
  const ExtinctionVolumes v = physics::buildExtinctionVolumes(io::openModelFile(path).load(0), physics::defaultOptics(),
                                                              physics::VerticalGridOptions{});
  std::filesystem::remove(path);
  const auto tex = render::VolumeTextures::upload(v, volume::frameOf(v, 8.0), "bench hurricane");
  const glm::dvec3 toSun = scene::Sun{120.0, 70.0}.toSun();
  render::RadianceVolume runs, everyCrossing(true), cpu;
  constexpr int kVariants = 3;
  render::RadianceVolume* variant[kVariants] = {&everyCrossing, &runs, &cpu};
  const render::RadianceVolumeBackend backend[kVariants] = {
      render::RadianceVolumeBackend::Gpu, render::RadianceVolumeBackend::Gpu, render::RadianceVolumeBackend::Cpu};
  std::vector<double> ms[kVariants];
  render::RadianceVolumeSettings s;
  s.photons = photons;
  s.photons_per_column = 0;
  int round = 0;
  for (auto _ : state) {
    double total = 0.0;
    for (int j = 0; j < kVariants; ++j) {
      const int k = (j + round) % kVariants;
      s.seed = std::uint32_t(16 + round);  // a new key: rebuilt; the GPU variants trace the same photons
      s.backend = backend[k];
      variant[k]->build(tex, toSun, s);
      ms[k].push_back(variant[k]->stats().build_ms);
      total += variant[k]->stats().build_ms;
    }
    ++round;
    state.SetIterationTime(total * 1e-3);
  }
  auto median = [](std::vector<double> x) {
    std::sort(x.begin(), x.end());
    return x.empty() ? 0.0 : x[x.size() / 2];
  };
  const render::RadianceVolumeStats& st = runs.stats();
  state.counters["every_crossing_ms"] = median(ms[0]);
  state.counters["runs_ms"] = median(ms[1]);
  state.counters["cpu_twin_ms"] = median(ms[2]);
  state.counters["ratio"] = median(ms[0]) / median(ms[1]);
  state.counters["runs_over_cpu"] = median(ms[1]) / median(ms[2]);
  state.counters["collisions_per_photon"] = double(st.collisions) / double(photons);
  state.counters["cpu_collisions_per_photon"] = double(cpu.stats().collisions) / double(photons);
  state.counters["dispatches"] = st.dispatches;
  std::fprintf(stderr,
               "radiance volume build, hurricane %dx%dx%d x8, %u photons, %d rounds on %s: every crossing %.0f ms, "
               "runs %.0f ms, CPU twin %.0f ms (medians); every crossing / runs %.2f, runs / CPU twin %.2f; %.1f "
               "collisions per photon (CPU twin %.1f), %d dispatches, %llu cut short\n",
               v.nx, v.ny, v.nz, photons, round, ctx->info().renderer.c_str(), median(ms[0]), median(ms[1]),
               median(ms[2]), median(ms[0]) / median(ms[1]), median(ms[1]) / median(ms[2]),
               double(st.collisions) / double(photons), double(cpu.stats().collisions) / double(photons), st.dispatches,
               static_cast<unsigned long long>(st.cut_short));
}
BENCHMARK(BM_RadianceVolumeBuild)
    ->ArgNames({"photons"})
    ->Arg(4096)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
