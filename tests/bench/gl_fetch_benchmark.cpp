// 3-D texture fetch throughput of a compute shader (glsl/bench/fetch3d.comp): the "physical
// limit" of a ray caster that only samples. Variants side by side in one run (these machines are
// noisy: compare ratios): filter (nearest / linear), texel format (R8, R16F, R32F) and ray
// direction (along x = the texture's fastest axis, along z = slowest, oblique).
// Time is wall time of dispatch + glFinish (manual time): llvmpipe's GL_TIME_ELAPSED queries do
// not cover the compute work it runs on its own threads, so they cannot drive the iteration count.
// The query's figure is still reported (counter gpu_query_ms) for drivers where it is meaningful.
// Run: make bench  (or build/tests/bench/nephele_gl_benchmarks --benchmark_filter=Fetch)
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include <fmt/format.h>

#include "core/error.h"
#include "fetch_kernel.h"
#include "render/gl/context.h"
#include "render/gl/debug.h"
#include "render/gl/objects.h"
#include "render/gl/program.h"

namespace {

using namespace nph;

gl::Context& context() {
  static std::unique_ptr<gl::Context> ctx = [] {
    gl::ContextOptions o;
    o.backend = gl::backendFromEnvironment();
    o.visible = false;
    o.debug = false;
    auto c = gl::createContext(o);
    std::fprintf(stderr, "benchmark context: %s (%s), %s, %s\n",
                 std::string(gl::backendName(c->info().backend)).c_str(), c->info().detail.c_str(),
                 c->info().renderer.c_str(), c->info().version.c_str());
    return c;
  }();
  return *ctx;
}

constexpr int kVolume = 128;  // 128^3 voxels
constexpr int kRays = 256;    // 256 x 256 rays
constexpr int kSteps = 128;   // samples per ray

gl::Texture makeVolume(GLenum format) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> data(std::size_t(kVolume) * kVolume * kVolume);
  for (float& v : data) v = u(rng);
  auto tex = gl::Texture::create3D(format, kVolume, kVolume, kVolume);
  glTextureSubImage3D(tex.id(), 0, 0, 0, 0, kVolume, kVolume, kVolume, GL_RED, GL_FLOAT, data.data());
  return tex;
}

enum Direction { AlongX = 0, AlongZ = 1, Oblique = 2 };

void BM_Fetch3D(benchmark::State& state) {
  context().makeCurrent();
  const GLenum format = static_cast<GLenum>(state.range(0));
  const GLenum filter = state.range(1) != 0 ? GL_LINEAR : GL_NEAREST;
  const auto direction = static_cast<Direction>(state.range(2));
  auto volume = makeVolume(format);
  volume.sampling(filter, GL_REPEAT);
  const bench::FetchKernel kernel({kRays, kRays}, kSteps);
  const float step = 1.0f / float(kSteps);
  const glm::vec3 dir = direction == AlongX   ? glm::vec3(step, 0, 0)
                        : direction == AlongZ ? glm::vec3(0, 0, step)
                                              : glm::vec3(step, step, step) * 0.57735f;
  gl::GpuTimer timer;
  auto run = [&] { kernel.dispatch(volume, dir); };
  run();  // warm-up: shader compile in the driver, texture upload
  glFinish();
  double queryNs = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    timer.start();
    run();
    timer.stop();
    glFinish();
    const auto t1 = std::chrono::steady_clock::now();
    state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
    queryNs += double(timer.elapsedNs());
  }
  state.counters["gpu_query_ms"] = queryNs * 1e-6 / double(state.iterations());
  gl::checkErrors("BM_Fetch3D");
  const double fetches = kernel.fetchesPerDispatch();
  state.counters["fetches_per_s"] =
      benchmark::Counter(fetches * double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["voxels"] = double(kVolume) * kVolume * kVolume;
  const char* formatName = format == GL_R8 ? "R8" : format == GL_R16F ? "R16F" : "R32F";
  const char* dirName = direction == AlongX ? "along-x" : direction == AlongZ ? "along-z" : "oblique";
  state.SetLabel(fmt::format("{} {} {}", formatName, filter == GL_LINEAR ? "linear" : "nearest", dirName));
}

void fetchArgs(benchmark::internal::Benchmark* b) {
  b->ArgNames({"format", "linear", "dir"});
  for (GLenum f : {GL_R8, GL_R16F, GL_R32F})
    for (int linear : {0, 1})
      for (int dir : {AlongX, AlongZ, Oblique}) b->Args({static_cast<long>(f), linear, dir});
}

BENCHMARK(BM_Fetch3D)->Apply(fetchArgs)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(0.3);

}  // namespace

BENCHMARK_MAIN();
