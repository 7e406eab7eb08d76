// Animation playback: sustained frames per second of a 1920 × 1080 animation of the realistic
// generated hurricane (500 × 500 × 60 at 3 km, hourly timesteps, height × 8, Blue Marble under it)
// on this machine's GL, with the prefetch thread on and off, side by side in one run, for two
// sources of timesteps: a .nph cache (decode ≈ 0.1–0.5 s a timestep) and the wrfout itself
// (NetCDF-4 read + optics on load, seconds a timestep: what prefetch is for; Nes 2008 §5.1.2).
//
// The animation is what a weather graphic does with hourly model output: the camera flies an arc
// (keyframes, Catmull–Rom) while the data steps from timestep to timestep (interpolation "step",
// sun fixed), so every frame is ray cast but the deep light map is rebuilt only when the timestep
// changes (Nes 2008 §6.3, table 6.1: a time change costs a volume upload and a DLM build, a camera
// change only the eye pass). Quality preset "draft" keeps the run to a few minutes on llvmpipe.
//
// Each variant runs twice (pass --benchmark_enable_random_interleaving=true to interleave the
// variants' runs against drifting machine load). Reported per run, aggregated as medians:
//   fps_sustained      (frames − 1) / time of frames 1..N−1 (the first frame's cold start excluded)
//   median_frame_ms    median wall time of one frame (setTime, setSun, render incl. read-back)
//   blocked_ms         time the render thread waited for timesteps (decode in its own thread or
//                      waiting for the prefetch worker), frames 1..N−1
//   dlm_reused_share   frames whose deep light map was reused / frames
//   peak_rss_mb        VmHWM of the process during the variant (reset through /proc/self/clear_refs)
//   peak_decoded_mb    decoded timesteps held at once (TimestepCache)
// Data: $NEPHELE_BENCH_ANIMATION_DIR (default $TMPDIR/nephele-animation-bench) holds
// wrfout-realistic.nc and hurricane-realistic.nph; they are generated there when missing (≈ 6 min,
// kept for the next run). NEPHELE_BENCH_SIZE=tiny runs the same on the tiny storm (seconds).
// Run: make bench, or build/tests/bench/nephele_animation_benchmarks
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "cache/nph_cache.h"
#include "engine/animation.h"
#include "engine/dataset.h"
#include "engine/session.h"
#include "presets.h"
#include "render/gl/context.h"
#include "scene/animation_spec.h"
#include "scene/scene_file.h"

namespace {

using namespace nph;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kTimesteps = 3;  ///< hourly timesteps animated (0 → 2)
constexpr int kFrames = 6;     ///< frames per variant
constexpr const char* kBlueMarble = "/usr/share/marble/data/maps/earth/bluemarble/bluemarble.jpg";

bool tiny() {
  const char* s = std::getenv("NEPHELE_BENCH_SIZE");
  return s && std::string(s) == "tiny";
}

fs::path dataDir() {
  if (const char* d = std::getenv("NEPHELE_BENCH_ANIMATION_DIR")) return d;
  return fs::temp_directory_path() / (tiny() ? "nephele-animation-bench-tiny" : "nephele-animation-bench");
}

/// The wrfout and the .nph of the same storm, generated once.
struct Data {
  std::string wrfout, nph;
};

const Data& data() {
  static const Data d = [] {
    Data out;
    const fs::path dir = dataDir();
    fs::create_directories(dir);
    out.wrfout = (dir / "wrfout-realistic.nc").string();
    out.nph = (dir / "hurricane-realistic.nph").string();
    if (!fs::exists(out.wrfout)) {
      std::fprintf(stderr, "animation benchmark: generating %s (once)\n", out.wrfout.c_str());
      datagen::WrfHurricaneSpec spec =
          datagen::wrfPreset(tiny() ? datagen::SampleSize::Tiny : datagen::SampleSize::Realistic);
      spec.ntimes = kTimesteps;
      datagen::writeWrfHurricane(spec, out.wrfout + ".partial");
      fs::rename(out.wrfout + ".partial", out.wrfout);
    }
    if (!fs::exists(out.nph)) {
      std::fprintf(stderr, "animation benchmark: converting to %s (once)\n", out.nph.c_str());
      const auto model = engine::Dataset::open(out.wrfout);
      std::unique_ptr<cache::NphWriter> writer;
      for (std::size_t t = 0; t < model->timestepCount(); ++t) {
        const ExtinctionVolumes v = model->load(t);
        if (!writer) {
          cache::NphMetadata meta;
          meta.nx = v.nx;
          meta.ny = v.ny;
          meta.dz_m = v.dz_m;
          meta.z_bottom_m = v.z_bottom_m;
          meta.georef = v.georef;
          meta.created_by = "nephele_animation_benchmarks";
          writer = std::make_unique<cache::NphWriter>(out.nph, meta);
        }
        writer->append(v);
      }
      writer->commit();
    }
    return out;
  }();
  return d;
}

gl::Context& context() {
  static std::unique_ptr<gl::Context> ctx = [] {
    gl::ContextOptions o;
    o.backend = gl::backendFromEnvironment();
    o.visible = false;
    return gl::createContext(o);
  }();
  return *ctx;
}

double vmHwmMb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::strtod(line.c_str() + 6, nullptr) / 1024.0;  // kB
  }
  return 0.0;
}

void resetPeakRss() { std::ofstream("/proc/self/clear_refs") << "5"; }

scene::SceneDescription benchScene(const std::string& path) {
  const std::string basemap = fs::exists(kBlueMarble) ? std::string(R"(, "basemap": { "path": ")") + kBlueMarble +
                                                            R"(", "margin": 0.4, "pixels_long_side": 2048 })"
                                                      : std::string();
  const int w = tiny() ? 320 : 1920, h = tiny() ? 180 : 1080;
  return scene::parseSceneText(R"({ "data": { "path": ")" + path + R"(" }, "camera": { "preset": "oblique" },
      "sun": { "azimuth_deg": 140, "elevation_deg": 35 }, "quality": "draft", "height_exaggeration": 8,
      "output": { "width": )" + std::to_string(w) +
                                   R"(, "height": )" + std::to_string(h) + "}" + basemap + R"(,
      "animation": { "from": 0, "to": )" +
                                   std::to_string(kTimesteps - 1) + R"(, "fps": 25, "duration_s": )" +
                                   std::to_string(double(kFrames - 1) / 25.0) + R"(, "interpolation": "step",
        "camera_keyframes": [ { "at_s": 0, "preset": "oblique", "azimuth_deg": 200 },
                              { "at_s": 0.2, "preset": "oblique", "azimuth_deg": 215, "distance_scale": 0.9 } ] } })",
                               "animation-benchmark");
}

void BM_Animation(benchmark::State& state, bool from_wrfout, bool prefetch) {
  const Data& d = data();
  gl::Context& ctx = context();
  (void)ctx;
  for (auto _ : state) {
    resetPeakRss();
    const auto dataset = engine::Dataset::open(from_wrfout ? d.wrfout : d.nph);
    const scene::SceneDescription s = benchScene(dataset->path());
    engine::Session session(dataset, s);
    const engine::AnimationPlan plan(scene::parseAnimation(s), *dataset, session.scene(), session.prepared());
    engine::PrefetchSettings p;  // as nephele animate sets it
    p.enabled = prefetch;
    p.first_timestep = std::size_t(plan.fromIndex());
    p.last_timestep = std::size_t(std::ceil(plan.toIndex()));
    session.setPrefetch(p);
    session.setPlaybackDirection(+1);
    std::vector<double> frame_ms;
    double blocked_ms = 0.0, steady_s = 0.0;
    int reused = 0;
    for (std::int64_t k = 0; k < plan.frameCount(); ++k) {
      const engine::AnimationFrame f = plan.frame(k);
      const auto t0 = Clock::now();
      session.setTime(f.time_index);
      session.setSun(f.sun);
      const auto out = session.render(f.camera);
      benchmark::DoNotOptimize(out.frame.rgba.data());
      const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      frame_ms.push_back(ms);
      reused += session.stats().dlm_rebuilt ? 0 : 1;
      if (k > 0) {
        steady_s += ms / 1000.0;
        blocked_ms += session.stats().blocked_ms;
      }
    }
    state.SetIterationTime(steady_s);
    std::vector<double> sorted = frame_ms;
    std::sort(sorted.begin(), sorted.end());
    state.counters["frames"] = double(frame_ms.size());
    state.counters["fps_sustained"] = double(frame_ms.size() - 1) / steady_s;
    state.counters["median_frame_ms"] = sorted[sorted.size() / 2];
    state.counters["first_frame_ms"] = frame_ms.front();
    state.counters["blocked_ms"] = blocked_ms;
    state.counters["dlm_reused_share"] = double(reused) / double(frame_ms.size());
    state.counters["peak_rss_mb"] = vmHwmMb();
    state.counters["peak_decoded_mb"] = double(session.prefetchStats().peak_bytes) / 1048576.0;
    state.counters["prefetched"] = double(session.prefetchStats().prefetched);
  }
}

// Side by side: each source with prefetch on and off, two runs each (≈ 7 min on 2 llvmpipe cores).
BENCHMARK_CAPTURE(BM_Animation, nph_prefetch_on, false, true)
    ->Iterations(1)
    ->Repetitions(2)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_Animation, nph_prefetch_off, false, false)
    ->Iterations(1)
    ->Repetitions(2)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_Animation, wrfout_prefetch_on, true, true)
    ->Iterations(1)
    ->Repetitions(2)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_Animation, wrfout_prefetch_off, true, false)
    ->Iterations(1)
    ->Repetitions(2)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
