// Frame time (issue 19): the eye pass and the deep light map build before and after issue 19's
// speed-ups, side by side in one interleaved run on the demo's view (oblique preset, 40°, sun
// 140°/35°, heights × 8). Variants, each round in a rotated order so that they share the load:
//   ray cast  old       one program for every view (uniform branches), DLM look-up by binary search
//             scan      + look-up by linear scan (glsl/dlm/lookup.glsl)
//             spec      + programs specialised per view at compile time (EyePassFeatures)
//             new       both (the default), with the packed texture (one fetch per step)
//             preset    new + the light cache of the broadcast preset (light_cache_voxels 2)
//   DLM build old       binary search in pass 2, pass 3 stopping at every scatter-slice centre,
//                       no pruning (DlmBaseline::no_pruning)
//             new       linear scan, pass 3 skipping across the scatter map's flat runs, pruned
//                       passes (the default)
//   fetch     the foundation's fetch kernel (fetch_kernel.h) on a volume of the scene's size and
//             format, the rate of a ray caster that does nothing but sample.
// Reported (medians over the rounds; ratio = old / new, > 1 is faster): wall ms and process CPU ms
// (llvmpipe's threads included) of each variant; the ray cast's volume samples per CPU-second as
// a fraction of the fetch kernel's fetches per CPU-second; and the differences the changes make:
// the eye-pass variants' frames must be equal bit for bit (counted: differing floats), the DLM
// build's in 8-bit sRGB levels of the frame (default exposure, ACES) and in |ΔI| of the light
// functions at every step of every texel.
// Scenes: `demo` = the realistic generated hurricane (500 × 500 × 60 at 3 km, the `make demo`
// storm), `coarse` = datagen::coarseStormSpec (72 × 64 × 30). Image width is the second argument
// (16:9); this 2-core VM renders the demo at 960 × 540.
// BM_DlmPruning (issue 19, session 15): the DLM build of the broadcast preset, pruned or not.
// BM_DlmAdaptiveStep (issue 19, session 16): the DLM's fixed light step against the adaptive one.
// BM_MultipleScatteringCost (issue 12): the broadcast frame with each multiple-scattering model
// (radiance_volume's eye pass since the seventeenth session).
// BM_EyePassDefaults (issue 19 item 1): light cache and adaptive steps against the direct path.
// BM_CloudResolution (issue 19 item 4): the clouds marched at 1/1, 1/2, 1/4 of the resolution.
// BM_DetailCost (issue 13): cubic reconstruction and sub-grid detail against the plain frame.
// BM_DetailMass (issue 13): the detail's mass measurement, exhaustive against cheaper patterns.
// BM_ReadBack (issue 19): render()'s read-back paths, with and without the cloud layer.
// Run: build/tests/bench/nephele_frame_benchmarks (part of make bench); docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bench_hurricane.h"
#include "bench_stats.h"
#include "fetch_kernel.h"
#include "lighting/knobs.h"
#include "reference/ray_marcher.h"
#include "render/dlm/deep_light_map.h"
#include "render/dlm/noise_texture.h"
#include "render/gl/context.h"
#include "render/raycast/cloud_renderer.h"
#include "scene/output_image.h"
#include "scene/scene_file.h"
#include "scene/sun.h"

namespace {

using namespace nph;

using bench::median;

// Wall and process CPU time of one call, in ms (CPU: all threads, so llvmpipe's workers count).
struct Timing {
  double wall_ms = 0.0, cpu_ms = 0.0;
};
template <class F>
Timing timed(F&& f) {
  const auto w0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  f();
  glFinish();
  Timing t;
  t.cpu_ms = 1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC;
  t.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - w0).count();
  return t;
}

struct Series {
  std::vector<double> wall, cpu;
  void add(const Timing& t) {
    wall.push_back(t.wall_ms);
    cpu.push_back(t.cpu_ms);
  }
};

// A DLM build's three pass times (wall ms, DlmStats) appended to per-pass series.
void addPassTimes(std::vector<double> (&pass)[3], const render::DlmStats& stats) {
  pass[0].push_back(stats.pass1_ms);
  pass[1].push_back(stats.pass2_ms);
  pass[2].push_back(stats.pass3_ms);
}

// Rounds of `variants` fresh DLM builds in rotating order, one round per benchmark iteration
// (BM_DlmPruning, BM_DlmAdaptiveStep): `prepare(map, k)` untimed (programs compiled), then
// `buildOne(map, k)` timed; wall and CPU per variant into `build`, the pass times into `pass`.
// Returns the rounds run.
template <class Prepare, class BuildOne>
int interleavedBuilds(benchmark::State& state, int variants, Series* build, std::vector<double> (*pass)[3],
                      Prepare&& prepare, BuildOne&& buildOne) {
  int round = 0;
  for (auto _ : state) {
    double total = 0.0;
    for (int j = 0; j < variants; ++j) {
      const int k = (j + round) % variants;
      render::DeepLightMap map;
      prepare(map, k);
      const Timing t = timed([&] { buildOne(map, k); });
      build[k].add(t);
      addPassTimes(pass[k], map.stats());
      total += t.wall_ms;
    }
    ++round;
    state.SetIterationTime(total * 1e-3);
  }
  return round;
}

long differingFloats(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size()) return long(std::max(a.size(), b.size()));
  long n = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    n += std::bit_cast<std::uint32_t>(a[i]) != std::bit_cast<std::uint32_t>(b[i]);
  return n;
}

// Largest difference of the 8-bit sRGB codes (default exposure, ACES) of two frames.
int maxLevelDifference(const scene::RgbaImage& a, const scene::RgbaImage& b) {
  scene::ImageOutputOptions o;
  o.exposure_ev = scene::kDefaultExposureEv;
  const auto ca = scene::encodeSrgb8(a, o), cb = scene::encodeSrgb8(b, o);
  int m = 0;
  for (std::size_t i = 0; i < ca.size() && i < cb.size(); ++i) m = std::max(m, std::abs(int(ca[i]) - int(cb[i])));
  return m;
}

// max |I_a − I_b| over every step of every texel of two maps of the same light space.
double maxLightDifference(const render::DeepLightMap& a, const render::DeepLightMap& b) {
  const auto ra = a.readBack(), rb = b.readBack();
  double m = 0.0;
  for (std::size_t t = 0; t < ra.nodes.size() && t < rb.nodes.size(); ++t) {
    for (int n = 0; n <= a.stats().steps; ++n) {
      const double s = n * a.stats().step_m;
      m = std::max(m, std::abs(lighting::evaluateLightFunction(ra.nodes[t].data(), int(ra.nodes[t].size()), s) -
                               lighting::evaluateLightFunction(rb.nodes[t].data(), int(rb.nodes[t].size()), s)));
    }
  }
  return m;
}

// The storm of a benchmark argument: the demo's realistic hurricane or the coarse storm.
ExtinctionVolumes benchVolumes(bool demo) {
  if (demo) return bench::realisticHurricane("nephele-frame-bench.nc");
  datagen::WrfHurricaneSpec spec = datagen::coarseStormSpec();
  spec.ntimes = 1;
  return bench::generatedVolumes(spec, "nephele-frame-bench.nc");
}

// The demo's view: the oblique preset at 40°.
scene::Camera demoCamera(const volume::VolumeFrame& frame, int width, int height) {
  scene::CameraSpec cs;
  cs.preset = scene::CameraPreset::Oblique;
  cs.fov_deg = 40.0;
  return scene::cameraFor(cs, frame, width, height);
}

void BM_FrameVariants(benchmark::State& state) {
  const bool demo = state.range(0) == 0;
  const int width = int(state.range(1)), height = width * 9 / 16;
  const auto ctx = bench::hiddenContext();
  const ExtinctionVolumes v = benchVolumes(demo);
  const auto frame = volume::frameOf(v, 8.0);
  const auto tex = render::VolumeTextures::upload(v, frame, "bench");
  const scene::Sun sun{140.0, 35.0};
  const scene::Camera camera = demoCamera(frame, width, height);
  const render::RenderSettings rs;
  const lighting::DlmSettings ds;

  // The DLM variants: built once here for the images, rebuilt (fresh objects) in the timed rounds.
  render::DeepLightMap dlmNew, dlmOld;
  dlmOld.setBaseline({.binary_search = true, .slice_breaks = true, .no_pruning = true});
  dlmNew.build(tex, -sun.toSun(), ds);
  dlmOld.build(tex, -sun.toSun(), ds);
  // The defaults of the broadcast preset (issue 19 item 1): the new eye pass reading the light
  // cache the preset bakes (light_cache_voxels 2) instead of the map's look-up.
  render::DeepLightMap dlmPreset;
  dlmPreset.build(tex, -sun.toSun(), lighting::dlmSettingsFor(lighting::qualityPreset(lighting::Preset::Broadcast)));

  // The eye-pass variants: one renderer each (each keeps its programs compiled).
  const render::EyePassBaseline eye[4] = {{.uniform_branches = true, .binary_search = true},
                                          {.uniform_branches = true, .binary_search = false},
                                          {.uniform_branches = false, .binary_search = true},
                                          {}};
  const char* eyeName[4] = {"old", "scan", "spec", "new"};
  render::CloudRenderer renderer[4];
  render::RenderOutput out[4];
  for (int k = 0; k < 4; ++k) {
    renderer[k].setBaseline(eye[k]);
    out[k] = renderer[k].render(tex, dlmNew, camera, sun, rs);  // compiles, warms up
  }
  // Bit for bit within each texture path: old = scan (separate textures: the uniform-branch program
  // has no packed texture), spec = new (packed); new against old in 8-bit levels (the packed
  // texture's half precision: LightCacheTest.PackedTextureDiffersOnlyAtTheTerminationThreshold).
  long differing = 0;
  for (const auto& [a, b] : {std::pair{0, 1}, std::pair{2, 3}}) {
    differing += differingFloats(out[a].frame.rgba, out[b].frame.rgba);
    differing += differingFloats(out[a].cloud_layer.rgba, out[b].cloud_layer.rgba);
  }
  const int packedLevels = maxLevelDifference(out[0].frame, out[3].frame);
  state.counters["packed_max_levels"] = packedLevels;
  std::fprintf(stderr, "  new (packed) against old (separate textures): frame max %d 8-bit levels\n", packedLevels);
  const render::RenderOutput withOldDlm = renderer[3].render(tex, dlmOld, camera, sun, rs);
  const int dlmLevels = maxLevelDifference(withOldDlm.frame, out[3].frame);
  const double dlmLight = maxLightDifference(dlmOld, dlmNew);
  renderer[3].countSamples(true);
  renderer[3].render(tex, dlmNew, camera, sun, rs);
  const double samples = double(renderer[3].sampleCount());
  renderer[3].countSamples(false);

  // The fetch kernel on a volume of the scene's size and format.
  auto volume = gl::Texture::create3D(GL_R32F, v.nx, v.ny, v.nz).label("fetch-limit volume");
  glTextureSubImage3D(volume.id(), 0, 0, 0, 0, v.nx, v.ny, v.nz, GL_RED, GL_FLOAT, v.water_per_m.data());
  volume.sampling(GL_LINEAR, GL_REPEAT);
  constexpr int kSteps = 128;
  const bench::FetchKernel kernel({width, height}, kSteps);
  const glm::vec3 step = glm::vec3(1.0f / kSteps) * 0.57735f;  // oblique, like the camera's rays
  kernel.dispatch(volume, step);                               // warm-up

  Series ray[5], dlm[2], fetch;   // ray[4]: the new eye pass with the preset's light cache
  std::vector<double> rayGpu[5];  // the dispatches' GPU time (GL_TIME_ELAPSED; ≈ 0 on llvmpipe)
  std::vector<double> pass[2][3];
  int round = 0;
  for (auto _ : state) {
    double total = 0.0;
    // Eight jobs per round (5 ray casts, 2 DLM builds, the fetch kernel), at a rotating offset.
    for (int j = 0; j < 8; ++j) {
      const int job = (j + round) % 8;
      Timing t;
      if (job < 5) {
        double gpuMs = 0.0;
        t = timed([&] {
          gpuMs =
              renderer[std::min(job, 3)].render(tex, job == 4 ? dlmPreset : dlmNew, camera, sun, rs).gpu_milliseconds;
        });
        ray[job].add(t);
        rayGpu[job].push_back(gpuMs);
      } else if (job < 7) {
        const int d = job - 5;  // 0 old, 1 new
        render::DeepLightMap map;
        if (d == 0) map.setBaseline({.binary_search = true, .slice_breaks = true, .no_pruning = true});
        t = timed([&] { map.build(tex, -sun.toSun(), ds); });
        dlm[d].add(t);
        addPassTimes(pass[d], map.stats());
      } else {
        t = timed([&] { kernel.dispatch(volume, step); });
        fetch.add(t);
      }
      total += t.wall_ms;
    }
    ++round;
    state.SetIterationTime(total * 1e-3);
  }

  auto& c = state.counters;
  for (int k = 0; k < 4; ++k) {
    c[std::string("ray_ms_") + eyeName[k]] = median(ray[k].wall);
    c[std::string("ray_cpu_ms_") + eyeName[k]] = median(ray[k].cpu);
  }
  for (int k = 0; k < 3; ++k) {
    c[std::string("ray_ratio_") + eyeName[k] + "_new"] = median(ray[k].wall) / median(ray[3].wall);
    c[std::string("ray_cpu_ratio_") + eyeName[k] + "_new"] = median(ray[k].cpu) / median(ray[3].cpu);
  }
  c["dlm_ms_old"] = median(dlm[0].wall);
  c["dlm_ms_new"] = median(dlm[1].wall);
  c["dlm_cpu_ms_old"] = median(dlm[0].cpu);
  c["dlm_cpu_ms_new"] = median(dlm[1].cpu);
  c["dlm_ratio"] = median(dlm[0].wall) / median(dlm[1].wall);
  c["dlm_cpu_ratio"] = median(dlm[0].cpu) / median(dlm[1].cpu);
  for (int p = 0; p < 3; ++p) {
    c["pass" + std::to_string(p + 1) + "_ms_old"] = median(pass[0][p]);
    c["pass" + std::to_string(p + 1) + "_ms_new"] = median(pass[1][p]);
  }
  const double fetchPerCpuS = kernel.fetchesPerDispatch() / (median(fetch.cpu) * 1e-3);
  const double samplesPerCpuS[3] = {samples / (median(ray[0].cpu) * 1e-3), samples / (median(ray[3].cpu) * 1e-3),
                                    samples / (median(ray[4].cpu) * 1e-3)};
  for (int k = 0; k < 5; ++k) c[std::string("ray_gpu_ms_") + (k < 4 ? eyeName[k] : "preset")] = median(rayGpu[k]);
  std::fprintf(
      stderr,
      "  ray cast   GPU ms (GL_TIME_ELAPSED; ~0 on llvmpipe) old %.2f  scan %.2f  spec %.2f  new %.2f  preset %.2f\n",
      median(rayGpu[0]), median(rayGpu[1]), median(rayGpu[2]), median(rayGpu[3]), median(rayGpu[4]));
  c["ray_ms_preset"] = median(ray[4].wall);
  c["ray_cpu_ms_preset"] = median(ray[4].cpu);
  c["ray_cpu_ratio_old_preset"] = median(ray[0].cpu) / median(ray[4].cpu);
  c["fraction_of_fetch_limit_preset"] = samplesPerCpuS[2] / fetchPerCpuS;
  c["fetches_per_cpu_s"] = fetchPerCpuS;
  c["samples"] = samples;
  c["fraction_of_fetch_limit_old"] = samplesPerCpuS[0] / fetchPerCpuS;
  c["fraction_of_fetch_limit_new"] = samplesPerCpuS[1] / fetchPerCpuS;
  c["eye_differing_floats"] = double(differing);
  c["dlm_max_levels"] = dlmLevels;
  c["dlm_max_abs_light"] = dlmLight;
  c["dlm_mean_nodes"] = dlmNew.stats().mean_nodes;

  std::fprintf(stderr,
               "frame benchmark, %s storm %dx%dx%d voxels, %dx%d pixels, %d rounds on %s\n"
               "  ray cast   wall ms old %.0f  scan %.0f  spec %.0f  new %.0f   old/new %.2f (scan %.2f, spec %.2f)\n"
               "             CPU ms  old %.0f  scan %.0f  spec %.0f  new %.0f   old/new %.2f\n"
               "             %.3g samples; %.3g samples per CPU-s = %.1f %% of the fetch kernel's %.3g "
               "fetches per CPU-s (old %.1f %%); frames differ in %ld floats\n"
               "  preset     (new + the broadcast preset's light cache) wall ms %.0f, CPU ms %.0f, old/preset CPU "
               "%.2f, %.1f %% of the fetch kernel's rate\n"
               "  DLM build  wall ms old %.0f (passes %.0f + %.0f + %.0f)  new %.0f (%.0f + %.0f + %.0f)  old/new %.2f;"
               " CPU old/new %.2f\n"
               "             max |dI| %.4f, frame max %d 8-bit levels; %.2f nodes per texel\n",
               demo ? "demo" : "coarse", v.nx, v.ny, v.nz, width, height, round, ctx->info().renderer.c_str(),
               median(ray[0].wall), median(ray[1].wall), median(ray[2].wall), median(ray[3].wall),
               median(ray[0].wall) / median(ray[3].wall), median(ray[1].wall) / median(ray[3].wall),
               median(ray[2].wall) / median(ray[3].wall), median(ray[0].cpu), median(ray[1].cpu), median(ray[2].cpu),
               median(ray[3].cpu), median(ray[0].cpu) / median(ray[3].cpu), samples, samplesPerCpuS[1],
               100.0 * samplesPerCpuS[1] / fetchPerCpuS, fetchPerCpuS, 100.0 * samplesPerCpuS[0] / fetchPerCpuS,
               differing, median(ray[4].wall), median(ray[4].cpu), median(ray[0].cpu) / median(ray[4].cpu),
               100.0 * samplesPerCpuS[2] / fetchPerCpuS, median(dlm[0].wall), median(pass[0][0]), median(pass[0][1]),
               median(pass[0][2]), median(dlm[1].wall), median(pass[1][0]), median(pass[1][1]), median(pass[1][2]),
               median(dlm[0].wall) / median(dlm[1].wall), median(dlm[0].cpu) / median(dlm[1].cpu), dlmLight, dlmLevels,
               dlmNew.stats().mean_nodes);
}
BENCHMARK(BM_FrameVariants)
    ->ArgNames({"scene", "width"})
    ->Args({1, 1920})  // coarse storm, 1920 × 1080
    ->Args({0, 960})   // demo storm, 960 × 540
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// Issue 19, session 15 ("nothing computed that a scene does not need"): the deep light map build of
// the broadcast preset (dlmSettingsFor(broadcast): 512 texels per side at most, 16 nodes, ε 0.01,
// the light cache ½) in three variants, interleaved in rotating order, fresh objects per build:
//   old     before issue 19 (binary search in pass 2, slice breaks in pass 3, no pruning)
//   s14     session 14's default: linear scan, flat runs, no pruning (DlmBaseline::no_pruning)
//   new     + pass 1 only at the texels pass 2 reads, pass 2 without the look-ups of clear cells,
//           the empty-space skip of passes 1 and 3 as a loop (the default)
// Reported: medians of wall and process CPU ms and of each pass, ratios s14/new and old/new, the
// texels pass 1 marched, texels whose node lists differ between s14 and new (must be 0: the pruning
// computes the same map) and max |ΔI| of new against old over every step of every texel.
void BM_DlmPruning(benchmark::State& state) {
  const bool demo = state.range(0) == 0;
  const auto ctx = bench::hiddenContext();
  const ExtinctionVolumes v = benchVolumes(demo);
  const auto frame = volume::frameOf(v, 8.0);
  const auto tex = render::VolumeTextures::upload(v, frame, "bench");
  const scene::Sun sun{140.0, 35.0};
  const lighting::DlmSettings ds = lighting::dlmSettingsFor(lighting::qualityPreset(lighting::Preset::Broadcast));
  const render::DlmBaseline baseline[3] = {
      {.binary_search = true, .slice_breaks = true, .no_pruning = true}, {.no_pruning = true}, {}};
  const char* name[3] = {"old", "s14", "new"};
  render::DeepLightMap maps[3];
  for (int k = 0; k < 3; ++k) {  // compiles, warms up; the maps compared below
    maps[k].setBaseline(baseline[k]);
    maps[k].build(tex, -sun.toSun(), ds);
  }
  const auto rs14 = maps[1].readBack(), rnew = maps[2].readBack();
  long differing = 0;
  for (std::size_t t = 0; t < rs14.nodes.size(); ++t) {
    bool same = rs14.nodes[t].size() == rnew.nodes[t].size();
    for (std::size_t k = 0; same && k < rs14.nodes[t].size(); ++k)
      same = rs14.nodes[t][k].depth_m == rnew.nodes[t][k].depth_m &&
             rs14.nodes[t][k].intensity == rnew.nodes[t][k].intensity;
    differing += same ? 0 : 1;
  }
  const double light = maxLightDifference(maps[0], maps[2]);
  Series build[3];
  std::vector<double> pass[3][3];
  const int round = interleavedBuilds(
      state, 3, build, pass, [&](render::DeepLightMap& map, int k) { map.setBaseline(baseline[k]); },
      [&](render::DeepLightMap& map, int) { map.build(tex, -sun.toSun(), ds); });
  auto& c = state.counters;
  for (int k = 0; k < 3; ++k) {
    c[std::string("dlm_ms_") + name[k]] = median(build[k].wall);
    c[std::string("dlm_cpu_ms_") + name[k]] = median(build[k].cpu);
    for (int p = 0; p < 3; ++p) c["pass" + std::to_string(p + 1) + "_ms_" + name[k]] = median(pass[k][p]);
  }
  c["ratio_s14_new"] = median(build[1].wall) / median(build[2].wall);
  c["cpu_ratio_s14_new"] = median(build[1].cpu) / median(build[2].cpu);
  c["ratio_old_new"] = median(build[0].wall) / median(build[2].wall);
  c["cpu_ratio_old_new"] = median(build[0].cpu) / median(build[2].cpu);
  c["differing_texels_s14_new"] = double(differing);
  c["max_abs_light_old_new"] = light;
  const render::DlmStats& st = maps[2].stats();
  std::fprintf(stderr,
               "DLM pruning, %s storm %dx%dx%d voxels, broadcast preset, %d rounds on %s\n"
               "  map %dx%d texels (pass 1: %lld), %d steps of %.0f m, scatter map %dx%dx%d, %.2f nodes per texel\n",
               demo ? "demo" : "coarse", v.nx, v.ny, v.nz, round, ctx->info().renderer.c_str(), st.texels.x,
               st.texels.y, static_cast<long long>(st.pass1_texels), st.steps, st.step_m, st.scatter_cells.x,
               st.scatter_cells.y, st.scatter_cells.z, st.mean_nodes);
  for (int k = 0; k < 3; ++k) {
    std::fprintf(stderr, "  %-4s wall %7.0f ms (passes %6.0f + %6.0f + %6.0f)  CPU %7.0f ms\n", name[k],
                 median(build[k].wall), median(pass[k][0]), median(pass[k][1]), median(pass[k][2]),
                 median(build[k].cpu));
  }
  std::fprintf(stderr,
               "  s14/new wall %.2f, CPU %.2f; old/new wall %.2f, CPU %.2f; texels differing s14/new %ld; "
               "max |dI| old/new %.4f\n",
               double(c["ratio_s14_new"]), double(c["cpu_ratio_s14_new"]), double(c["ratio_old_new"]),
               double(c["cpu_ratio_old_new"]), differing, light);
}
BENCHMARK(BM_DlmPruning)
    ->ArgNames({"scene"})
    ->Arg(1)  // coarse storm
    ->Arg(0)  // demo storm
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// Issue 19, session 16: the adaptive light step of the DLM march (DlmSettings::step_growth_max;
// glsl/dlm/march.comp). The broadcast preset's build with the fixed step Δ = ½ voxel (`fixed`) and
// runs of up to 2 and 4 Δ where the occupancy brick bounds β within the per-ray budget ε/2
// (`g2`, `g4`; pass 3's runs end at scatter-slice centres, 4 Δ apart at broadcast, so more would
// only lengthen pass 1's), interleaved in rotating order, fresh objects per build. Storms: the coarse
// storm (1), the smooth realistic hurricane (0) and the cellular hurricane of `make demo`
// (2: WrfCase::HurricaneCells, realistic size). Reported: medians of wall and process CPU ms and
// of each pass, fixed/variant ratios, and max |ΔI| against the fixed step over every step of every
// texel (bound 2.5 ε: each map within ε of its samples, the samples within the budget ε/2).
void BM_DlmAdaptiveStep(benchmark::State& state) {
  const int scene = int(state.range(0));
  const auto ctx = bench::hiddenContext();
  ExtinctionVolumes v;
  if (scene == 2) {
    datagen::WrfHurricaneSpec spec = datagen::wrfPreset(datagen::SampleSize::Realistic);
    spec.ntimes = 1;
    spec.weather = datagen::WrfCase::HurricaneCells;
    v = bench::generatedVolumes(spec, "nephele-frame-bench.nc");
  } else {
    v = benchVolumes(scene == 0);
  }
  const auto frame = volume::frameOf(v, 8.0);
  const auto tex = render::VolumeTextures::upload(v, frame, "bench");
  const scene::Sun sun{140.0, 35.0};
  constexpr int kVariants = 3;
  const int growth[kVariants] = {1, 2, 4};
  const char* name[kVariants] = {"fixed", "g2", "g4"};
  lighting::DlmSettings ds[kVariants];
  render::DeepLightMap maps[kVariants];
  for (int k = 0; k < kVariants; ++k) {  // compiles, warms up; the maps compared below
    ds[k] = lighting::dlmSettingsFor(lighting::qualityPreset(lighting::Preset::Broadcast));
    ds[k].step_growth_max = growth[k];
    maps[k].build(tex, -sun.toSun(), ds[k]);
  }
  double light[kVariants] = {0.0};
  for (int k = 1; k < kVariants; ++k) light[k] = maxLightDifference(maps[0], maps[k]);
  // Item 2 of the session's brief (merge passes 2 and 3?): pass 2 is one dispatch per scatter slice
  // with a barrier after each. Their fixed cost on this GL, measured as as many dispatches of the
  // fetch kernel on one 8 × 8 workgroup of one fetch each, with the same barrier (medians of 5).
  const int sliceDispatches = maps[0].stats().scatter_cells.z - 1;
  std::vector<double> dispatchWall, dispatchCpu;
  {
    const bench::FetchKernel tiny({8, 8}, 1);
    auto one = gl::Texture::create3D(GL_R32F, 1, 1, 1);
    for (int r = 0; r < 5; ++r) {
      const Timing t = timed([&] {
        for (int k = 0; k < sliceDispatches; ++k) {
          tiny.dispatch(one, glm::vec3(0.0f, 0.0f, 0.01f));
          glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        }
      });
      dispatchWall.push_back(t.wall_ms);
      dispatchCpu.push_back(t.cpu_ms);
    }
  }
  Series build[kVariants];
  std::vector<double> pass[kVariants][3];
  const int round = interleavedBuilds(
      state, kVariants, build, pass, [](render::DeepLightMap&, int) {},
      [&](render::DeepLightMap& map, int k) { map.build(tex, -sun.toSun(), ds[k]); });
  auto& c = state.counters;
  for (int k = 0; k < kVariants; ++k) {
    c[std::string("dlm_ms_") + name[k]] = median(build[k].wall);
    c[std::string("dlm_cpu_ms_") + name[k]] = median(build[k].cpu);
    for (int p = 0; p < 3; ++p) c["pass" + std::to_string(p + 1) + "_ms_" + name[k]] = median(pass[k][p]);
    if (k > 0) {
      c[std::string("ratio_fixed_") + name[k]] = median(build[0].wall) / median(build[k].wall);
      c[std::string("cpu_ratio_fixed_") + name[k]] = median(build[0].cpu) / median(build[k].cpu);
      c[std::string("max_abs_light_") + name[k]] = light[k];
    }
  }
  c["pass2_dispatch_overhead_ms"] = median(dispatchWall);
  const render::DlmStats& st = maps[0].stats();
  const char* storm[3] = {"demo (smooth)", "coarse", "cellular"};
  std::fprintf(stderr,
               "DLM adaptive step, %s storm %dx%dx%d voxels, broadcast preset, %d rounds on %s\n"
               "  map %dx%d texels (pass 1: %lld), %d steps of %.0f m, scatter map %dx%dx%d, %.2f nodes per texel\n",
               storm[scene], v.nx, v.ny, v.nz, round, ctx->info().renderer.c_str(), st.texels.x, st.texels.y,
               static_cast<long long>(st.pass1_texels), st.steps, st.step_m, st.scatter_cells.x, st.scatter_cells.y,
               st.scatter_cells.z, st.mean_nodes);
  std::fprintf(stderr, "  pass 2: %d dispatches, their fixed cost (empty dispatches) %.1f ms wall, %.1f ms CPU\n",
               sliceDispatches, median(dispatchWall), median(dispatchCpu));
  for (int k = 0; k < kVariants; ++k) {
    const render::DlmStats& sk = maps[k].stats();
    std::fprintf(stderr, "  %-5s %lld steps marched, %lld (%.0f %%) in %lld runs; %d texels overflowed (ε doubled)\n",
                 name[k], static_cast<long long>(sk.marched_steps), static_cast<long long>(sk.run_steps),
                 100.0 * double(sk.run_steps) / double(std::max<std::int64_t>(sk.marched_steps, 1)),
                 static_cast<long long>(sk.runs), sk.overflowed_texels);
  }
  for (int k = 0; k < kVariants; ++k) {
    std::fprintf(stderr,
                 "  %-5s wall %7.0f ms (passes %6.0f + %6.0f + %6.0f)  CPU %7.0f ms  fixed/this wall %.2f CPU %.2f  "
                 "max |dI| %.4f  nodes %.2f\n",
                 name[k], median(build[k].wall), median(pass[k][0]), median(pass[k][1]), median(pass[k][2]),
                 median(build[k].cpu), median(build[0].wall) / median(build[k].wall),
                 median(build[0].cpu) / median(build[k].cpu), light[k], maps[k].stats().mean_nodes);
  }
}
BENCHMARK(BM_DlmAdaptiveStep)
    ->ArgNames({"scene"})
    ->Arg(1)  // coarse storm
    ->Arg(0)  // smooth realistic hurricane
    ->Arg(2)  // cellular hurricane (make demo's)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// Issue 12 (third phase): the broadcast frame (DLM build + ray cast) with each multiple-scattering
// model of the knob `multiple_scattering`, interleaved in rotating order. The DLM is the same for
// every model, so it is timed once per round and added to each cast. Reported: medians of wall and
// CPU ms, and the frame-time ratios to the octaves (the default before issue 12's third phase).
void BM_MultipleScatteringCost(benchmark::State& state) {
  const bool demo = state.range(0) == 0;
  const int width = int(state.range(1)), height = width * 9 / 16;
  const auto ctx = bench::hiddenContext();
  const ExtinctionVolumes v = benchVolumes(demo);
  const auto frame = volume::frameOf(v, 8.0);
  const auto tex = render::VolumeTextures::upload(v, frame, "bench");
  const scene::Sun sun{140.0, 35.0};
  const scene::Camera camera = demoCamera(frame, width, height);
  const lighting::DlmSettings ds;
  render::DeepLightMap dlm;
  dlm.build(tex, -sun.toSun(), ds);
  // lighting::MultipleScattering: single, octaves, two_stream, radiance_volume (seventeenth session:
  // its volume is traced on the warm-up render and cached, as with the map — the rounds time the
  // eye pass only; state.range(2) photons, the build's own cost is BM_RadianceVolumeBuild's)
  constexpr int kModels = 4;
  render::RenderSettings rs[kModels];
  render::CloudRenderer renderer[kModels];
  render::RadianceVolumeSettings rv;
  rv.photons = std::uint32_t(state.range(2));
  renderer[3].setRadianceVolumeSettings(rv);
  double rvBuildMs = 0.0;
  for (int k = 0; k < kModels; ++k) {
    rs[k].multiple_scattering = lighting::MultipleScattering(k);
    const Timing warm = timed([&] { renderer[k].render(tex, dlm, camera, sun, rs[k]); });  // compiles, warms up
    if (k == 3) rvBuildMs = warm.wall_ms;
  }
  Series cast[kModels], build;
  int round = 0;
  for (auto _ : state) {
    double total = 0.0;
    for (int j = 0; j <= kModels; ++j) {
      const int job = (j + round) % (kModels + 1);
      Timing t;
      if (job < kModels) {
        t = timed([&] { renderer[job].render(tex, dlm, camera, sun, rs[job]); });
        cast[job].add(t);
      } else {
        render::DeepLightMap map;
        t = timed([&] { map.build(tex, -sun.toSun(), ds); });
        build.add(t);
      }
      total += t.wall_ms;
    }
    ++round;
    state.SetIterationTime(total * 1e-3);
  }
  const double d = median(build.wall), dc = median(build.cpu);
  auto& c = state.counters;
  for (int k = 0; k < kModels; ++k) {
    const std::string name(lighting::kMultipleScatteringNames[std::size_t(k)]);
    c["cast_ms_" + name] = median(cast[k].wall);
    c["cast_cpu_ms_" + name] = median(cast[k].cpu);
    c["frame_ratio_" + name] = (d + median(cast[k].wall)) / (d + median(cast[1].wall));
    c["frame_cpu_ratio_" + name] = (dc + median(cast[k].cpu)) / (dc + median(cast[1].cpu));
  }
  c["dlm_ms"] = d;
  c["cast_ratio_radiance_volume_to_two_stream"] = median(cast[3].wall) / median(cast[2].wall);
  c["frame_ratio_radiance_volume_to_two_stream"] = (d + median(cast[3].wall)) / (d + median(cast[2].wall));
  std::fprintf(stderr,
               "multiple scattering cost, %s storm %dx%dx%d voxels, %dx%d pixels, %d rounds on %s\n"
               "  DLM build wall %.0f ms (CPU %.0f); ray cast wall ms single %.0f, octaves %.0f, two_stream %.0f, "
               "radiance_volume %.0f (CPU %.0f, %.0f, %.0f, %.0f)\n"
               "  frame (DLM + cast) two_stream / octaves: wall %.3f, CPU %.3f; single / octaves: wall %.3f\n"
               "  radiance_volume / two_stream: cast wall %.3f, CPU %.3f; frame wall %.3f (its volume, %lld photons, "
               "traced once with the warm-up frame: %.0f ms)\n",
               demo ? "demo" : "coarse", v.nx, v.ny, v.nz, width, height, round, ctx->info().renderer.c_str(), d, dc,
               median(cast[0].wall), median(cast[1].wall), median(cast[2].wall), median(cast[3].wall),
               median(cast[0].cpu), median(cast[1].cpu), median(cast[2].cpu), median(cast[3].cpu),
               double(c["frame_ratio_two_stream"]), double(c["frame_cpu_ratio_two_stream"]),
               double(c["frame_ratio_single"]), median(cast[3].wall) / median(cast[2].wall),
               median(cast[3].cpu) / median(cast[2].cpu), double(c["frame_ratio_radiance_volume_to_two_stream"]),
               static_cast<long long>(state.range(2)), rvBuildMs);
}
BENCHMARK(BM_MultipleScatteringCost)
    ->ArgNames({"scene", "width", "photons"})
    ->Args({1, 1280, 65536})  // coarse storm, 1280 × 720
    ->Args({1, 640, 16384})   // coarse storm, 640 × 360 (seventeenth session's run)
    ->Args({0, 960, 65536})   // demo storm, 960 × 540
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(7);

// Issue 12: the cost of a change to the eye pass's light, against the pass without it (an
// EyePassBaseline), same storm, camera and DLM as BM_MultipleScatteringCost, ray casts interleaved
// in rotating order; medians over the rounds, ratio = new / old (wall and process CPU). `what`
// names the measurement, `oldName`/`newName` the two passes (counters cast_ms_<name>).
void baselineCastCost(benchmark::State& state, const render::EyePassBaseline& baseline, const char* what,
                      const std::string& oldName, const std::string& newName) {
  const bool demo = state.range(0) == 0;
  const int width = int(state.range(1)), height = width * 9 / 16;
  const auto ctx = bench::hiddenContext();
  const ExtinctionVolumes v = benchVolumes(demo);
  const auto frame = volume::frameOf(v, 8.0);
  const auto tex = render::VolumeTextures::upload(v, frame, "bench");
  const scene::Sun sun{140.0, 35.0};
  const scene::Camera camera = demoCamera(frame, width, height);
  render::DeepLightMap dlm;
  dlm.build(tex, -sun.toSun(), lighting::DlmSettings{});
  const render::RenderSettings rs;
  render::CloudRenderer renderer[2];  // 0: the baseline, 1: the default
  renderer[0].setBaseline(baseline);
  for (auto& r : renderer) r.render(tex, dlm, camera, sun, rs);  // compiles, warms up
  Series cast[2];
  int round = 0;
  for (auto _ : state) {
    double total = 0.0;
    for (int j = 0; j < 2; ++j) {
      const int job = (j + round) % 2;
      const Timing t = timed([&] { renderer[job].render(tex, dlm, camera, sun, rs); });
      cast[job].add(t);
      total += t.wall_ms;
    }
    ++round;
    state.SetIterationTime(total * 1e-3);
  }
  auto& c = state.counters;
  c["cast_ms_" + oldName] = median(cast[0].wall);
  c["cast_ms_" + newName] = median(cast[1].wall);
  c["cast_ratio"] = median(cast[1].wall) / median(cast[0].wall);
  c["cast_cpu_ratio"] = median(cast[1].cpu) / median(cast[0].cpu);
  std::fprintf(stderr,
               "%s, %s storm %dx%dx%d voxels, %dx%d pixels, %d rounds on %s\n"
               "  ray cast wall ms %s %.0f, %s %.0f (CPU %.0f, %.0f): ratio wall %.3f, CPU %.3f\n",
               what, demo ? "demo" : "coarse", v.nx, v.ny, v.nz, width, height, round, ctx->info().renderer.c_str(),
               oldName.c_str(), median(cast[0].wall), newName.c_str(), median(cast[1].wall), median(cast[0].cpu),
               median(cast[1].cpu), double(c["cast_ratio"]), double(c["cast_cpu_ratio"]));
}

// Issue 12, twelfth session: the sky term's cost. The eye pass with skyDiffuse (the default) against
// the former ½·(L_above·T_d(τ_up) + L_below·T_d(τ_down)) (EyePassBaseline::sky_half_transmittance).
void BM_SkyTermCost(benchmark::State& state) {
  render::EyePassBaseline former;
  former.sky_half_transmittance = true;
  baselineCastCost(state, former, "sky term cost", "former", "sky_diffuse");
}
BENCHMARK(BM_SkyTermCost)
    ->ArgNames({"scene", "width"})
    ->Args({1, 640})  // coarse storm, 640 × 360
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(9);

// Issue 12, thirteenth session: the cost of the forward lobe (glsl/common/cloud_light.glsl
// forwardLobe: an exp and two HG lobes per sample) against two_stream without it
// (EyePassBaseline::no_forward_lobe).
void BM_ForwardLobeCost(benchmark::State& state) {
  render::EyePassBaseline without;
  without.no_forward_lobe = true;
  baselineCastCost(state, without, "forward lobe cost", "without", "forward_lobe");
}
BENCHMARK(BM_ForwardLobeCost)
    ->ArgNames({"scene", "width"})
    ->Args({1, 640})  // coarse storm, 640 × 360
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(9);

// Issue 19 item 1: the eye pass's sampling options measured together under the default light
// model (two_stream), to choose the defaults: the DLM's direct look-up (the reference path), the
// light cache (DlmSettings::light_cache_voxels; glsl/dlm/light_cache.comp) at ½ and ¼ of the
// volume's resolution, adaptive steps (RenderSettings::step_growth_max; Muth 2026 eq. 3.6;
// glsl/render/clouds.comp adaptiveStep, clipped at the brick face, and the first, unclipped
// version) and both together; all with the packed texture (VolumeTextures::hasPacked, one fetch
// per step), and the direct path once more with the separate textures (three fetches per step). The ray casts are
// interleaved in rotating order; the bake is timed inside each cache's DLM build (one build each). Errors in 8-bit sRGB
// levels (default exposure, ACES; mean, 99th percentile, max and the share of values more than 2 levels off): each
// frame (default settings) against the direct path's frame, and each cloud layer (no jitter, no atmosphere, which the
// reference lacks) against the CPU reference ray marcher evaluating the map per sample at the fixed step
// (reference::marchCloudLayer). Also the volume samples per frame.
struct LevelStats {
  double mean = 0.0, p99 = 0.0;
  int max = 0;
  double over2 = 0.0;  ///< share of values differing by more than 2 levels
};
LevelStats levelStats(const scene::RgbaImage& a, const scene::RgbaImage& b) {
  scene::ImageOutputOptions o;
  o.exposure_ev = scene::kDefaultExposureEv;
  const auto ca = scene::encodeSrgb8(a, o), cb = scene::encodeSrgb8(b, o);
  std::vector<int> d(std::min(ca.size(), cb.size()));
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = std::abs(int(ca[i]) - int(cb[i]));
  LevelStats l;
  if (d.empty()) return l;
  double sum = 0.0;
  std::size_t over = 0;
  for (const int x : d) {
    sum += x;
    over += x > 2;
    l.max = std::max(l.max, x);
  }
  l.mean = sum / double(d.size());
  l.over2 = double(over) / double(d.size());
  const auto nth = d.begin() + std::ptrdiff_t(double(d.size() - 1) * 0.99);
  std::nth_element(d.begin(), nth, d.end());
  l.p99 = *nth;
  return l;
}

// The demo's view of a benchmark storm: the volumes uploaded, the sun of the demo, the oblique
// camera, and the CPU reference ray marcher's cloud layer for a map (no jitter, no atmosphere:
// referenceSettings).
struct DemoScene {
  bool demo;
  int width, height;
  std::unique_ptr<gl::Context> ctx = bench::hiddenContext();
  ExtinctionVolumes v = benchVolumes(demo);
  volume::VolumeFrame frame = volume::frameOf(v, 8.0);
  // Both copies (VolumeStorage::Reference): the separate-textures variant reads its own R32F/RG16F
  // textures, and every map is built from float β as when these variants were chosen.
  render::VolumeTextures tex =
      render::VolumeTextures::upload(v, frame, "bench", {.storage = render::VolumeStorage::Reference});
  scene::Sun sun{140.0, 35.0};
  scene::Camera camera = demoCamera(frame, width, height);

  static render::RenderSettings referenceSettings() {
    render::RenderSettings rs;
    rs.jitter = false;
    rs.atmosphere = false;
    return rs;
  }
  scene::RgbaImage cpuReference(const render::DeepLightMap& dlm) const {
    const auto map = dlm.readBack();
    const auto& ls = dlm.lightSpace();
    return reference::marchCloudLayer(
        v, frame, camera, sun, [&](const glm::dvec3& p) { return render::DeepLightMap::lookup(map, ls, p); },
        referenceSettings());
  }
};

// kVariants ray casts per round in rotating order (cast(k) renders variant k); returns the rounds.
template <int kVariants, class Cast>
int interleavedCasts(benchmark::State& state, Series (&series)[kVariants], Cast&& cast) {
  int round = 0;
  for (auto _ : state) {
    double total = 0.0;
    for (int j = 0; j < kVariants; ++j) {
      const int k = (j + round) % kVariants;
      const Timing t = timed([&] { cast(k); });
      series[k].add(t);
      total += t.wall_ms;
    }
    ++round;
    state.SetIterationTime(total * 1e-3);
  }
  return round;
}

void BM_EyePassDefaults(benchmark::State& state) {
  const DemoScene sc{state.range(0) == 0, int(state.range(1)), int(state.range(1)) * 9 / 16};
  struct Variant {
    const char* name;
    double cache_voxels;  ///< DlmSettings::light_cache_voxels (0: the direct look-up)
    double growth;        ///< RenderSettings::step_growth_max (1: fixed steps)
    int renderer;         ///< 0 the default eye pass, 1 unclipped steps, 2 separate textures
  };
  constexpr int kVariants = 8;
  const Variant variants[kVariants] = {{"direct", 0, 1, 0},
                                       {"direct_separate", 0, 1, 2},
                                       {"cache_half", 2, 1, 0},
                                       {"cache_quarter", 4, 1, 0},
                                       {"adaptive4", 0, 4, 0},
                                       {"adaptive4_unclipped", 0, 4, 1},
                                       {"cache_half+adaptive4", 2, 4, 0},
                                       {"cache_quarter+adaptive4", 4, 4, 0}};
  // One map per cache cell size (the bake runs inside the build), one renderer per baseline.
  std::vector<std::unique_ptr<render::DeepLightMap>> maps;
  std::vector<double> cells;
  std::vector<double> bakeMs, buildMs;
  auto mapFor = [&](double cell) -> const render::DeepLightMap& {
    for (std::size_t i = 0; i < cells.size(); ++i)
      if (cells[i] == cell) return *maps[i];
    lighting::DlmSettings ds;
    ds.light_cache_voxels = cell;
    maps.push_back(std::make_unique<render::DeepLightMap>());
    buildMs.push_back(timed([&] { maps.back()->build(sc.tex, -sc.sun.toSun(), ds); }).wall_ms);
    bakeMs.push_back(maps.back()->stats().light_cache_ms);
    cells.push_back(cell);
    return *maps.back();
  };
  render::CloudRenderer renderers[3];
  renderers[1].setBaseline({.unclipped_steps = true});
  renderers[2].setBaseline({.separate_textures = true});
  const scene::RgbaImage cpu = sc.cpuReference(mapFor(0.0));
  render::RenderSettings rs[kVariants];
  render::RenderOutput out[kVariants];
  LevelStats vsDirect[kVariants], vsCpu[kVariants];
  double samples[kVariants];
  auto cast = [&](int k, const render::RenderSettings& settings) {
    const Variant& var = variants[k];
    return renderers[var.renderer].render(sc.tex, mapFor(var.cache_voxels), sc.camera, sc.sun, settings);
  };
  for (int k = 0; k < kVariants; ++k) {
    const Variant& var = variants[k];
    rs[k].step_growth_max = var.growth;
    render::RenderSettings ref = DemoScene::referenceSettings();
    ref.step_growth_max = var.growth;
    render::CloudRenderer& r = renderers[var.renderer];
    r.countSamples(true);
    out[k] = cast(k, rs[k]);  // compiles, warms up
    samples[k] = double(r.sampleCount());
    r.countSamples(false);
    vsCpu[k] = levelStats(cast(k, ref).cloud_layer, cpu);
  }
  for (int k = 0; k < kVariants; ++k) vsDirect[k] = levelStats(out[k].frame, out[0].frame);
  Series series[kVariants];
  const int rounds = interleavedCasts<kVariants>(state, series, [&](int k) { cast(k, rs[k]); });

  std::fprintf(stderr, "eye-pass defaults (%s), %s storm %dx%dx%d voxels, %dx%d pixels, %d rounds on %s\n",
               std::string(lighting::kMultipleScatteringNames[std::size_t(rs[0].multiple_scattering)]).c_str(),
               sc.demo ? "demo" : "coarse", sc.v.nx, sc.v.ny, sc.v.nz, sc.width, sc.height, rounds,
               sc.ctx->info().renderer.c_str());
  auto& c = state.counters;
  for (int k = 0; k < kVariants; ++k) {
    const Variant& var = variants[k];
    const std::string name = var.name;
    std::size_t m = 0;
    while (cells[m] != var.cache_voxels) ++m;
    const double ratio = median(series[0].cpu) / median(series[k].cpu);
    c["cast_ms_" + name] = median(series[k].wall);
    c["cast_cpu_ms_" + name] = median(series[k].cpu);
    c["cast_cpu_ratio_" + name] = ratio;
    c["samples_" + name] = samples[k];
    c["levels_vs_direct_p99_" + name] = vsDirect[k].p99;
    c["levels_vs_direct_max_" + name] = vsDirect[k].max;
    c["levels_vs_cpu_p99_" + name] = vsCpu[k].p99;
    c["levels_vs_cpu_max_" + name] = vsCpu[k].max;
    const glm::ivec3 n = maps[m]->stats().light_cache_texels;
    std::fprintf(stderr,
                 "  %-24s ray cast wall %6.0f ms, CPU %6.0f ms, direct/this %.2f; %.3g samples; cache %dx%dx%d, bake "
                 "%.0f ms (DLM build %.0f ms)\n"
                 "  %-24s vs direct: mean %.3f p99 %.0f max %d, %.3f %% > 2; vs CPU reference: mean %.3f p99 %.0f "
                 "max %d, %.3f %% > 2\n",
                 var.name, median(series[k].wall), median(series[k].cpu), ratio, samples[k], n.x, n.y, n.z, bakeMs[m],
                 buildMs[m], "", vsDirect[k].mean, vsDirect[k].p99, vsDirect[k].max, 100.0 * vsDirect[k].over2,
                 vsCpu[k].mean, vsCpu[k].p99, vsCpu[k].max, 100.0 * vsCpu[k].over2);
  }
}
BENCHMARK(BM_EyePassDefaults)
    ->ArgNames({"scene", "width"})
    ->Args({1, 1280})  // coarse storm, 1280 × 720
    ->Args({0, 640})   // demo storm, 640 × 360
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// Issue 19 item 4: reduced-resolution clouds (RenderSettings::cloud_resolution, the knob
// `cloud_resolution`; glsl/render/clouds.comp upsampleClouds): the eye pass with the clouds
// marched at 1/1, 1/2 and 1/4 of the width and height and upsampled (depth-aware) under the ground
// drawn at full resolution, the broadcast defaults otherwise (light cache ½), interleaved in
// rotating order. Errors in 8-bit sRGB levels (as BM_EyePassDefaults): each frame against the
// full-resolution frame, and each cloud layer (no jitter, no atmosphere) against the CPU reference
// ray marcher at full resolution (reference::marchCloudLayer, the map's direct look-up per sample).
void BM_CloudResolution(benchmark::State& state) {
  const DemoScene sc{state.range(0) == 0, int(state.range(1)), int(state.range(1)) * 9 / 16};
  constexpr int kVariants = 3;
  const int divisors[kVariants] = {1, 2, 4};
  lighting::DlmSettings ds;
  ds.light_cache_voxels = lighting::QualitySettings{}.light_cache_voxels;  // the broadcast preset's
  render::DeepLightMap dlm;
  dlm.build(sc.tex, -sc.sun.toSun(), ds);
  render::DeepLightMap direct;  // the CPU reference evaluates the map itself, not its cache
  direct.build(sc.tex, -sc.sun.toSun(), lighting::DlmSettings{});
  const scene::RgbaImage cpu = sc.cpuReference(direct);
  render::CloudRenderer renderer;
  render::RenderSettings rs[kVariants];
  render::RenderOutput out[kVariants];
  LevelStats vsFull[kVariants], vsCpu[kVariants];
  double samples[kVariants];
  for (int k = 0; k < kVariants; ++k) {
    rs[k].cloud_resolution = divisors[k];
    render::RenderSettings ref = DemoScene::referenceSettings();
    ref.cloud_resolution = divisors[k];
    renderer.countSamples(true);
    out[k] = renderer.render(sc.tex, dlm, sc.camera, sc.sun, rs[k]);  // compiles, warms up
    samples[k] = double(renderer.sampleCount());
    renderer.countSamples(false);
    vsCpu[k] = levelStats(renderer.render(sc.tex, dlm, sc.camera, sc.sun, ref).cloud_layer, cpu);
  }
  for (int k = 0; k < kVariants; ++k) vsFull[k] = levelStats(out[k].frame, out[0].frame);
  Series series[kVariants];
  const int rounds = interleavedCasts<kVariants>(state, series, [&](int k) {
    renderer.dispatch(sc.tex, dlm, render::ViewRays::fromCamera(sc.camera), sc.sun, rs[k]);
  });
  std::fprintf(stderr, "cloud resolution, %s storm %dx%dx%d voxels, %dx%d pixels, %d rounds on %s\n",
               sc.demo ? "demo" : "coarse", sc.v.nx, sc.v.ny, sc.v.nz, sc.width, sc.height, rounds,
               sc.ctx->info().renderer.c_str());
  auto& c = state.counters;
  for (int k = 0; k < kVariants; ++k) {
    const std::string name = "1_" + std::to_string(divisors[k]);
    const double cpuRatio = median(series[0].cpu) / median(series[k].cpu);
    const double wallRatio = median(series[0].wall) / median(series[k].wall);
    c["cast_ms_" + name] = median(series[k].wall);
    c["cast_cpu_ms_" + name] = median(series[k].cpu);
    c["cast_cpu_ratio_" + name] = cpuRatio;
    c["levels_vs_full_max_" + name] = vsFull[k].max;
    c["levels_vs_cpu_max_" + name] = vsCpu[k].max;
    std::fprintf(stderr,
                 "  clouds at 1/%d: eye pass wall %6.0f ms, CPU %6.0f ms, full/this wall %.2f CPU %.2f; %.3g samples\n"
                 "  %-13s vs full resolution: mean %.3f p99 %.0f max %d, %.3f %% > 2; cloud layer vs CPU reference: "
                 "mean %.3f p99 %.0f max %d, %.3f %% > 2\n",
                 divisors[k], median(series[k].wall), median(series[k].cpu), wallRatio, cpuRatio, samples[k], "",
                 vsFull[k].mean, vsFull[k].p99, vsFull[k].max, 100.0 * vsFull[k].over2, vsCpu[k].mean, vsCpu[k].p99,
                 vsCpu[k].max, 100.0 * vsCpu[k].over2);
  }
}
BENCHMARK(BM_CloudResolution)
    ->ArgNames({"scene", "width"})
    ->Args({0, 960})   // demo storm, 960 × 540 (the CPU reference at 1080p takes too long on the 2-core VM)
    ->Args({1, 1920})  // coarse storm, 1920 × 1080
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// Issue 13: the cost of the smooth reconstruction and of the sub-grid detail (volume/detail.h,
// glsl/common/detail.glsl; Muth 2026 §3.3.1), each against the plain trilinear frame, on the demo's
// view: six uploads (trilinear / cubic × detail none / subtle / full), each with its own deep light
// map (the DLM's passes read the same filtered, detailed field), ray cast at the broadcast defaults
// in rotating order. The upload (controls, noise tile, GPU mass correction) and the DLM build are
// timed once per variant (a build is cached by its key); the ray casts are the interleaved medians.
// Also reported: volume samples per frame and the frame's difference from the plain frame in 8-bit
// levels (what the detail adds to the picture, not an error).
void BM_DetailCost(benchmark::State& state) {
  const DemoScene sc{state.range(0) == 0, int(state.range(1)), int(state.range(1)) * 9 / 16};
  struct Variant {
    const char* name;
    volume::Reconstruction reconstruction;
    volume::Detail detail;
    bool still_air = false;  ///< U, V dropped: the noise world-fixed, read once per phase pair
  };
  constexpr int kVariants = 7;
  using R = volume::Reconstruction;
  using D = volume::Detail;
  const Variant variants[kVariants] = {{"trilinear", R::Trilinear, D::None},
                                       {"trilinear+subtle", R::Trilinear, D::Subtle},
                                       {"trilinear+full", R::Trilinear, D::Full},
                                       {"cubic", R::Cubic, D::None},
                                       {"cubic+subtle", R::Cubic, D::Subtle},
                                       {"cubic+full", R::Cubic, D::Full},
                                       {"trilinear+full,still", R::Trilinear, D::Full, true}};
  // The storm without its wind (issue 13, the advection's cost: "trilinear+full" against this).
  ExtinctionVolumes still = sc.v;
  still.wind_u_m_per_s.clear();
  still.wind_v_m_per_s.clear();
  std::vector<std::unique_ptr<render::VolumeTextures>> tex;
  std::vector<std::unique_ptr<render::DeepLightMap>> maps;
  double uploadMs[kVariants], buildMs[kVariants], samples[kVariants];
  std::shared_ptr<const render::NoiseTexture> noise;
  for (int k = 0; k < kVariants; ++k) {
    const Variant& var = variants[k];
    uploadMs[k] = timed([&] {
                    tex.push_back(std::make_unique<render::VolumeTextures>(render::VolumeTextures::upload(
                        var.still_air ? still : sc.v, sc.frame, std::string("bench|") + var.name,
                        {.reconstruction = var.reconstruction, .detail = var.detail, .noise = noise})));
                  }).wall_ms;
    if (!noise && tex.back()->noise()) noise = tex.back()->noise();
    maps.push_back(std::make_unique<render::DeepLightMap>());
    buildMs[k] = timed([&] { maps.back()->build(*tex.back(), -sc.sun.toSun(), lighting::DlmSettings{}); }).wall_ms;
  }
  render::CloudRenderer renderer;
  const render::RenderSettings rs;
  render::RenderOutput out[kVariants];
  auto cast = [&](int k) {
    return renderer.render(*tex[std::size_t(k)], *maps[std::size_t(k)], sc.camera, sc.sun, rs);
  };
  for (int k = 0; k < kVariants; ++k) {
    renderer.countSamples(true);
    out[k] = cast(k);  // compiles the variant's program, warms up
    samples[k] = double(renderer.sampleCount());
    renderer.countSamples(false);
  }
  Series series[kVariants];
  const int rounds = interleavedCasts<kVariants>(state, series, [&](int k) { cast(k); });

  std::fprintf(stderr, "detail cost, %s storm %dx%dx%d voxels, %dx%d pixels, %d rounds on %s; noise advected: %s\n",
               sc.demo ? "demo" : "coarse", sc.v.nx, sc.v.ny, sc.v.nz, sc.width, sc.height, rounds,
               sc.ctx->info().renderer.c_str(), tex[2]->hasDetailWind() ? "yes (U, V)" : "no (no U, V)");
  auto& c = state.counters;
  for (int k = 0; k < kVariants; ++k) {
    const std::string name = variants[k].name;
    const LevelStats d = levelStats(out[k].frame, out[0].frame);
    const double ratio = median(series[k].cpu) / median(series[0].cpu);
    c["cast_ms_" + name] = median(series[k].wall);
    c["cast_cpu_ms_" + name] = median(series[k].cpu);
    c["cast_cpu_ratio_" + name] = ratio;
    c["upload_ms_" + name] = uploadMs[k];
    c["dlm_ms_" + name] = buildMs[k];
    c["samples_" + name] = samples[k];
    std::fprintf(stderr,
                 "  %-18s ray cast wall %7.0f ms, CPU %7.0f ms, this/plain %.2f; upload %6.0f ms, DLM build %6.0f ms; "
                 "%.3g samples; vs plain: mean %.2f p99 %.0f max %d levels\n",
                 variants[k].name, median(series[k].wall), median(series[k].cpu), ratio, uploadMs[k], buildMs[k],
                 samples[k], d.mean, d.p99, d.max);
  }
}
BENCHMARK(BM_DetailCost)
    ->ArgNames({"scene", "width"})
    ->Args({1, 640})  // coarse storm, 640 × 360
    ->Args({0, 640})  // demo storm, 640 × 360 (detail full: minutes per frame on llvmpipe)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// Issue 13, "a cheaper mass measurement" (docs/detail.md): the detail's GPU mass measurement
// (VolumeTextures::measureRayMasses, glsl/render/detail_mass.comp) with the exhaustive
// pattern of the tenth session against cheaper ones (volume/detail.h MassPattern: only the occupied
// footprints and layers, fewer rays, a coarser step), coarse storm, detail full, the filter of the
// second argument. Timed: the measurement alone (compile, range upload, dispatch, read-back), in
// rotating order, medians. Accuracy against the exhaustive c_J: max and rms of |c/c_exh − 1| (the
// relative change of the column's corrected optical mass) over the footprints with plain mass and
// over those with τ ≥ 1; and a detail frame (the demo view, 640 × 360, each pattern's own upload
// and DLM) against the exhaustive pattern's, in 8-bit levels.
void BM_DetailMass(benchmark::State& state) {
  const bool cubic = state.range(0) == 1;
  const int width = 640, height = 360;
  const auto ctx = bench::hiddenContext();
  const ExtinctionVolumes v = benchVolumes(false);
  const volume::VolumeFrame frame = volume::frameOf(v, 8.0);
  const scene::Sun sun{140.0, 35.0};
  const scene::Camera camera = demoCamera(frame, width, height);
  const volume::Reconstruction r = cubic ? volume::Reconstruction::Cubic : volume::Reconstruction::Trilinear;
  struct Variant {
    const char* name;
    volume::MassPattern pattern;
  };
  constexpr int kVariants = 6;
  const Variant variants[kVariants] = {{"exhaustive", volume::kExhaustiveMassPattern},
                                       {"occupied", {2, 0.25, true}},
                                       {"occupied+step_half", {2, 0.5, true}},
                                       {"occupied+step_1", {2, 1.0, true}},
                                       {"occupied+step_2", {2, 2.0, true}},
                                       {"occupied+1ray+step_1", {1, 1.0, true}}};
  std::shared_ptr<const render::NoiseTexture> noise;
  std::vector<std::unique_ptr<render::VolumeTextures>> tex;
  render::CloudRenderer renderer;
  const render::RenderSettings rs;
  render::RenderOutput out[kVariants];
  std::vector<float> c[kVariants];
  volume::RayMasses exhaustive;
  double samples[kVariants], uploadMs[kVariants];
  for (int k = 0; k < kVariants; ++k) {
    const volume::MassPattern& p = variants[k].pattern;
    uploadMs[k] = timed([&] {
                    tex.push_back(std::make_unique<render::VolumeTextures>(render::VolumeTextures::upload(
                        v, frame, "bench-mass",
                        {.reconstruction = r, .detail = volume::Detail::Full, .noise = noise, .mass = p})));
                  }).wall_ms;
    if (!noise) noise = tex.back()->noise();
    render::DeepLightMap dlm;
    dlm.build(*tex.back(), -sun.toSun(), lighting::DlmSettings{});
    out[k] = renderer.render(*tex.back(), dlm, camera, sun, rs);
    const volume::RayMasses m = tex.back()->measureRayMasses(v, p);
    if (k == 0) exhaustive = m;
    c[k] = volume::solveDetailCorrection(m);
    const int filterReach = volume::reachVoxels(r);
    samples[k] = volume::massSampleCount(
        volume::massStepRanges(v, filterReach, filterReach + tex.back()->detail().reach_voxels, p), p);
  }
  // Footprints with plain mass and their optical depth (exhaustive pattern, data metres).
  const int nx = v.nx, ny = v.ny;
  std::vector<double> plain(std::size_t(nx) * std::size_t(ny), 0.0);
  double maxPlain = 0.0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      double& P = plain[std::size_t(j) * std::size_t(nx) + std::size_t(i)];
      P = exhaustive.plainOf(i, j);
      maxPlain = std::max(maxPlain, P);
    }
  const double tauPerSum = volume::kMassStepLayers * frame.voxel_size_m.z / frame.height_exaggeration /
                           double(4 * volume::kMassRaysPerAxis * volume::kMassRaysPerAxis);
  Series series[kVariants];
  const int rounds = interleavedCasts<kVariants>(
      state, series, [&](int k) { (void)tex[std::size_t(k)]->measureRayMasses(v, variants[k].pattern); });
  std::fprintf(stderr, "detail mass measurement, coarse storm %dx%dx%d voxels, %s, detail full, %d rounds on %s\n",
               v.nx, v.ny, v.nz, cubic ? "cubic" : "trilinear", rounds, ctx->info().renderer.c_str());
  auto& counters = state.counters;
  for (int k = 0; k < kVariants; ++k) {
    double maxAll = 0.0, sumAll = 0.0, maxThick = 0.0, sumThick = 0.0, maxThin = 0.0;
    int nAll = 0, nThick = 0, nThin = 0, thinOver5 = 0;
    for (std::size_t J = 0; J < plain.size(); ++J) {
      if (!(plain[J] > 1e-6 * maxPlain)) continue;
      const double e = std::abs(double(c[k][J]) / double(c[0][J]) - 1.0);
      maxAll = std::max(maxAll, e);
      sumAll += e * e;
      ++nAll;
      const double tau = plain[J] * tauPerSum;
      if (tau >= 1.0) {
        maxThick = std::max(maxThick, e);
        sumThick += e * e;
        ++nThick;
      } else if (tau >= 0.1) {
        maxThin = std::max(maxThin, e);
        thinOver5 += e > 0.05;
        ++nThin;
      }
    }
    const double rmsAll = std::sqrt(sumAll / std::max(nAll, 1)), rmsThick = std::sqrt(sumThick / std::max(nThick, 1));
    const LevelStats d = levelStats(out[k].frame, out[0].frame);
    const double ratio = median(series[0].wall) / median(series[k].wall);
    const std::string name = variants[k].name;
    counters["mass_ms_" + name] = median(series[k].wall);
    counters["speedup_" + name] = ratio;
    counters["upload_ms_" + name] = uploadMs[k];
    counters["samples_" + name] = samples[k];
    counters["c_max_rel_" + name] = maxAll;
    counters["c_rms_rel_" + name] = rmsAll;
    counters["c_max_rel_thick_" + name] = maxThick;
    counters["c_max_rel_thin_" + name] = maxThin;
    counters["image_max_levels_" + name] = d.max;
    std::fprintf(
        stderr,
        "  %-24s measurement %8.0f ms (exhaustive/this %5.1f×), upload %6.0f ms, %.3g samples per field; "
        "c vs exhaustive over %d footprints with mass: max %.2f %% rms %.3f %%, over %d with tau >= 1: max "
        "%.2f %% rms %.3f %%, over %d with 0.1 <= tau < 1: max %.2f %%, %d over 5 %%; %ld of %zu c differ in bits; "
        "frame vs exhaustive: mean %.3f p99 %.0f max %d levels\n",
        variants[k].name, median(series[k].wall), ratio, uploadMs[k], samples[k], nAll, 100.0 * maxAll, 100.0 * rmsAll,
        nThick, 100.0 * maxThick, 100.0 * rmsThick, nThin, 100.0 * maxThin, thinOver5, differingFloats(c[k], c[0]),
        c[k].size(), d.mean, d.p99, d.max);
  }
}
BENCHMARK(BM_DetailMass)
    ->ArgNames({"cubic"})
    ->Arg(0)
    ->Arg(1)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// Issue 19, twenty-third session: render()'s read-back. On the H200 render() took 110–142 ms of
// wall time for 2.1 ms of GPU work (docs/benchmarks.md "On an NVIDIA GPU"). The same frame, read
// back each way (render::ReadBack): glGetTextureImage into fresh vectors (direct, the former path
// and llvmpipe's default) and through the renderer's pixel-pack buffer (pbo, a GPU's default),
// each with the cloud layer and without it (_frame: what `nephele render` reads when no file
// takes the layer). Interleaved in rotating order; medians of render()'s wall time and of its
// parts (RenderOutput: set-up and submission, wait, read-back). The pbo images must equal
// direct's bit for bit. (Half floats through the pack buffer, measured in the twenty-third
// session on the H200: read-back 89 ms against 23 ms in float — the driver converts on the CPU;
// docs/benchmarks.md "Read-back".)
void BM_ReadBack(benchmark::State& state) {
  const DemoScene sc{state.range(0) == 0, int(state.range(1)), int(state.range(1)) * 9 / 16};
  lighting::DlmSettings ds = lighting::dlmSettingsFor(lighting::qualityPreset(lighting::Preset::Broadcast));
  render::DeepLightMap dlm;
  dlm.build(sc.tex, -sc.sun.toSun(), ds);
  using Path = render::ReadBack::Path;
  struct Variant {
    const char* name;
    render::ReadBack read_back;
  };
  constexpr int kVariants = 4;
  const Variant variants[kVariants] = {{"direct", {true, Path::Direct}},
                                       {"pbo", {true, Path::PixelBuffer}},
                                       {"direct_frame", {false, Path::Direct}},
                                       {"pbo_frame", {false, Path::PixelBuffer}}};
  render::CloudRenderer renderer;
  const render::RenderSettings rs;
  render::RenderOutput out[kVariants];
  for (int k = 0; k < kVariants; ++k)
    out[k] = renderer.render(sc.tex, dlm, sc.camera, sc.sun, rs, variants[k].read_back);  // compiles, warms up
  Series series[kVariants];
  std::vector<double> submit[kVariants], wait[kVariants], copy[kVariants], gpu[kVariants];
  const int rounds = interleavedCasts<kVariants>(state, series, [&](int k) {
    const render::RenderOutput o = renderer.render(sc.tex, dlm, sc.camera, sc.sun, rs, variants[k].read_back);
    submit[k].push_back(o.submit_milliseconds);
    wait[k].push_back(o.wait_milliseconds);
    copy[k].push_back(o.readback_milliseconds);
    gpu[k].push_back(o.gpu_milliseconds);
  });
  std::fprintf(stderr, "read-back, %s storm %dx%dx%d voxels, %dx%d pixels, broadcast light cache, %d rounds on %s\n",
               sc.demo ? "demo" : "coarse", sc.v.nx, sc.v.ny, sc.v.nz, sc.width, sc.height, rounds,
               sc.ctx->info().renderer.c_str());
  auto& c = state.counters;
  for (int k = 0; k < kVariants; ++k) {
    const std::string name = variants[k].name;
    // Against direct with the same images: bit-identical.
    const render::RenderOutput& ref = out[variants[k].read_back.cloud_layer ? 0 : 2];
    const long bits = differingFloats(out[k].frame.rgba, ref.frame.rgba) +
                      differingFloats(out[k].cloud_layer.rgba, ref.cloud_layer.rgba);
    const int levels = maxLevelDifference(out[k].frame, ref.frame);
    c["ms_" + name] = median(series[k].wall);
    c["readback_ms_" + name] = median(copy[k]);
    c["speedup_" + name] = median(series[0].wall) / median(series[k].wall);
    c["differing_floats_" + name] = double(bits);
    c["max_levels_" + name] = levels;
    std::fprintf(stderr,
                 "  %-15s render() wall %7.1f ms (direct/this %5.2f×, CPU %7.1f ms): set-up and submission %6.1f, "
                 "wait %6.1f, read-back %6.1f ms, GPU %6.2f ms; vs direct: %ld floats differ, max %d levels\n",
                 variants[k].name, median(series[k].wall), median(series[0].wall) / median(series[k].wall),
                 median(series[k].cpu), median(submit[k]), median(wait[k]), median(copy[k]), median(gpu[k]), bits,
                 levels);
  }
}
BENCHMARK(BM_ReadBack)
    ->ArgNames({"scene", "width"})
    ->Args({1, 960})  // coarse storm, 960 × 540: the read-back depends on the pixels, not the storm
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);

// Issue 19 item 4, twenty-fourth session: the temporal accumulation of the interactive path
// (RenderSettings::temporal_history; render/raycast/temporal_accumulation.h). The draft preset's
// march (as `nephele view` draws while the camera moves: step 1 voxel, clouds at ½ resolution),
// the camera orbiting the demo view's target by 0.1° per frame; each variant its own renderer (its
// own history), the frames interleaved in rotating order: off (every frame on its own) and N = 4
// (the viewer's). Reported: the frame's wall and CPU time (the dispatch with glFinish) and, after
// the run, each variant's last frame against the same march at 16 samples per pixel of that camera
// in 8-bit levels (levelStats). The three frames are written to the working directory as
// temporal-{off,n4,converged}.png for docs/rendering.md.
void BM_TemporalAccumulation(benchmark::State& state) {
  const DemoScene sc{state.range(0) == 0, int(state.range(1)), int(state.range(1)) * 9 / 16};
  const lighting::QualitySettings draft = lighting::qualityPreset(lighting::Preset::Draft);
  render::DeepLightMap dlm;
  dlm.build(sc.tex, -sc.sun.toSun(), lighting::dlmSettingsFor(draft));
  const render::RenderSettings base = lighting::renderSettingsFor(draft, lighting::StyleSettings{});
  constexpr int kVariants = 2;
  const int histories[kVariants] = {0, 4};
  const char* names[kVariants] = {"off", "n4"};
  render::CloudRenderer renderers[kVariants];
  render::RenderSettings rs[kVariants] = {base, base};
  int frames[kVariants] = {0, 0};
  const auto cameraAt = [&](int frame) {  // the demo camera turned about the vertical through its target
    scene::Camera c = sc.camera;
    const double a = glm::radians(0.1 * frame);
    const glm::dvec3 d = c.position_m - c.target_m;
    c.position_m =
        c.target_m + glm::dvec3(d.x * std::cos(a) - d.y * std::sin(a), d.x * std::sin(a) + d.y * std::cos(a), d.z);
    return c;
  };
  for (int k = 0; k < kVariants; ++k) {
    rs[k].temporal_history = histories[k];
    renderers[k].render(sc.tex, dlm, cameraAt(frames[k]++), sc.sun, rs[k]);  // compiles, warms up
  }
  Series series[kVariants];
  const int rounds = interleavedCasts<kVariants>(state, series, [&](int k) {
    renderers[k].dispatch(sc.tex, dlm, render::ViewRays::fromCamera(cameraAt(frames[k]++)), sc.sun, rs[k]);
  });
  // The last frames (one more each, read back) against the converged picture of their camera.
  render::RenderOutput last[kVariants];
  for (int k = 0; k < kVariants; ++k) last[k] = renderers[k].render(sc.tex, dlm, cameraAt(frames[k]), sc.sun, rs[k]);
  render::RenderSettings converged = base;
  converged.samples_per_pixel = 16;
  render::CloudRenderer reference;
  const render::RenderOutput truth = reference.render(sc.tex, dlm, cameraAt(frames[0]), sc.sun, converged);
  std::fprintf(stderr,
               "temporal accumulation, %s storm %dx%dx%d voxels, %dx%d pixels, draft march, orbit 0.1 deg per frame, "
               "%d rounds on %s\n",
               sc.demo ? "demo" : "coarse", sc.v.nx, sc.v.ny, sc.v.nz, sc.width, sc.height, rounds,
               sc.ctx->info().renderer.c_str());
  auto& c = state.counters;
  for (int k = 0; k < kVariants; ++k) {
    const LevelStats e = levelStats(last[k].frame, truth.frame);
    const std::string name = names[k];
    c["ms_" + name] = median(series[k].wall);
    c["cpu_ms_" + name] = median(series[k].cpu);
    c["levels_mean_" + name] = e.mean;
    std::fprintf(stderr,
                 "  %-4s frame wall %7.1f ms (this/off %.3f), CPU %7.1f ms (%.3f); last frame vs 16 spp: mean %.3f "
                 "p99 %.0f max %d, %.2f %% > 2 levels\n",
                 names[k], median(series[k].wall), median(series[k].wall) / median(series[0].wall),
                 median(series[k].cpu), median(series[k].cpu) / median(series[0].cpu), e.mean, e.p99, e.max,
                 100.0 * e.over2);
    scene::writePng(last[k].frame, std::string("temporal-") + names[k] + ".png");
  }
  scene::writePng(truth.frame, "temporal-converged.png");
}
BENCHMARK(BM_TemporalAccumulation)
    ->ArgNames({"scene", "width"})
    ->Args({0, 640})  // demo storm, 640 × 360
    ->Args({1, 640})  // coarse storm, 640 × 360
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(12);

// On a real GPU (tools/gpu_bench.sh sets NEPHELE_BENCH_WIDTH=1920) the demo storm at that width too,
// with more rounds: the frame-size runs above are sized for llvmpipe on a 2-core machine.
const int kWideRuns = [] {
  const char* env = std::getenv("NEPHELE_BENCH_WIDTH");
  const int width = env ? std::atoi(env) : 0;
  if (width < 64 || width > 8192) return 0;
  const auto wide = [](const char* name, void (*fn)(benchmark::State&)) {
    return benchmark::RegisterBenchmark(name, fn)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(9);
  };
  wide("BM_FrameVariants", BM_FrameVariants)->ArgNames({"scene", "width"})->Args({0, width});
  wide("BM_EyePassDefaults", BM_EyePassDefaults)->ArgNames({"scene", "width"})->Args({0, width});
  wide("BM_DetailCost", BM_DetailCost)->ArgNames({"scene", "width"})->Args({0, width});
  wide("BM_ReadBack", BM_ReadBack)->ArgNames({"scene", "width"})->Args({0, width});
  wide("BM_MultipleScatteringCost", BM_MultipleScatteringCost)
      ->ArgNames({"scene", "width", "photons"})
      ->Args({0, width, 65536});
  return 5;
}();

}  // namespace

BENCHMARK_MAIN();
