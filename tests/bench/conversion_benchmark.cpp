// Conversion pipeline benchmarks (`nephele convert` stages side by side, one run): NetCDF read
// (uncompressed classic vs NetCDF-4 deflate) vs optics vs vertical resampling vs cache write
// (zstd levels) vs cache read. Throughput is given in MB of model fields per second
// (bytes_per_second), so stages compare directly; compare ratios and medians, not absolutes.
// The scene is the synthetic hurricane of data_tools, 200x200x40 by default;
// NEPHELE_BENCH_SIZE=realistic uses the 500x500x60 preset (slow to generate: minutes).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "cache/nph_cache.h"
#include "io/model_file.h"
#include "physics/extinction.h"
#include "physics/vertical_resampling.h"
#include "physics/volume_builder.h"
#include "presets.h"

namespace {

namespace fs = std::filesystem;
using namespace nph;

/// Generated once per process: one classic and one deflated file, and a loaded timestep.
struct Scene {
  fs::path dir;
  std::string classic, deflate;
  io::ModelTimestep ts;
  physics::ModelLevelExtinction beta;
  ExtinctionVolumes volumes;
  std::int64_t field_bytes = 0;

  Scene() {
    dir = fs::temp_directory_path() / ("nephele-bench-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const char* size = std::getenv("NEPHELE_BENCH_SIZE");
    datagen::WrfHurricaneSpec spec;
    if (size != nullptr && std::string(size) == "realistic") {
      spec = datagen::wrfPreset(datagen::SampleSize::Realistic);
    } else {
      spec.nx = 200;
      spec.ny = 200;
      spec.nz = 40;
      spec.dx_m = 7500.0;
    }
    spec.ntimes = 1;
    classic = (dir / "wrfout_classic.nc").string();
    deflate = (dir / "wrfout_deflate.nc").string();
    spec.format = datagen::NcFormat::Classic64;
    datagen::writeWrfHurricane(spec, classic);
    spec.format = datagen::NcFormat::Netcdf4Deflate;
    datagen::writeWrfHurricane(spec, deflate);
    ts = io::openModelFile(classic).load(0);
    std::size_t floats = ts.pressure_pa.size() + ts.temperature_k.size() + ts.height_m.size() +
                         ts.water_vapour_kg_per_kg.size() + ts.terrain_height_m.size();
    for (const auto& [h, v] : ts.q_kg_per_kg) floats += v.size();
    for (const auto& [h, v] : ts.number_per_kg) floats += v.size();
    field_bytes = std::int64_t(floats * sizeof(float));
    beta = physics::modelLevelExtinction(ts, physics::defaultOptics());
    volumes = physics::buildExtinctionVolumes(ts, physics::defaultOptics(), {});
  }
  ~Scene() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

Scene& scene() {
  static Scene s;
  return s;
}

void setRate(benchmark::State& state) {
  state.SetBytesProcessed(std::int64_t(state.iterations()) * scene().field_bytes);
  state.counters["voxels"] = double(scene().ts.voxelCount());
}

void BM_ReadNetcdfClassic(benchmark::State& state) {
  const io::ModelFile f = io::openModelFile(scene().classic);
  for (auto _ : state) benchmark::DoNotOptimize(f.load(0));
  setRate(state);
}
BENCHMARK(BM_ReadNetcdfClassic)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ReadNetcdfDeflate(benchmark::State& state) {
  const io::ModelFile f = io::openModelFile(scene().deflate);
  for (auto _ : state) benchmark::DoNotOptimize(f.load(0));
  setRate(state);
}
BENCHMARK(BM_ReadNetcdfDeflate)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Optics(benchmark::State& state) {
  const physics::OpticsSettings s = physics::defaultOptics();
  for (auto _ : state) benchmark::DoNotOptimize(physics::modelLevelExtinction(scene().ts, s));
  setRate(state);
}
BENCHMARK(BM_Optics)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ResamplePchip(benchmark::State& state) {
  const physics::VerticalGrid g = physics::planVerticalGrid(scene().ts, scene().beta, {});
  for (auto _ : state) {
    ExtinctionVolumes v;
    physics::resampleVertically(scene().ts, scene().beta, g, v);
    benchmark::DoNotOptimize(v.ice_per_m.data());
  }
  setRate(state);
  state.counters["nz_out"] = double(g.nz);
}
BENCHMARK(BM_ResamplePchip)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_CacheWrite(benchmark::State& state) {
  const ExtinctionVolumes& v = scene().volumes;
  cache::NphMetadata m;
  m.nx = v.nx;
  m.ny = v.ny;
  m.dz_m = v.dz_m;
  m.z_bottom_m = v.z_bottom_m;
  cache::WriterOptions o;
  o.zstd_level = int(state.range(0));
  const fs::path out = scene().dir / "bench.nph";
  for (auto _ : state) {
    cache::NphWriter w(out, m, o);
    w.append(v);
    w.commit();
  }
  setRate(state);
  const double raw = double(v.voxelCount() * 2 * sizeof(std::uint16_t));
  state.counters["compression_ratio"] = raw / double(fs::file_size(out));
}
BENCHMARK(BM_CacheWrite)->Arg(1)->Arg(3)->Arg(9)->Unit(benchmark::kMillisecond)->UseRealTime();

// Arg: 1 with the timestep's U, V (the wind chunk, cache/nph_cache.h), 0 without (files before it).
void BM_CacheRead(benchmark::State& state) {
  ExtinctionVolumes v = scene().volumes;
  if (state.range(0) == 0) {
    v.wind_u_m_per_s.clear();
    v.wind_v_m_per_s.clear();
  }
  cache::NphMetadata m;
  m.nx = v.nx;
  m.ny = v.ny;
  m.dz_m = v.dz_m;
  m.z_bottom_m = v.z_bottom_m;
  const fs::path out = scene().dir / "read.nph";
  {
    cache::NphWriter w(out, m);
    w.append(v);
    w.commit();
  }
  const cache::NphReader r(out);
  for (auto _ : state) benchmark::DoNotOptimize(r.read(0));
  state.SetBytesProcessed(std::int64_t(state.iterations()) * std::int64_t(v.voxelCount() * 2 * sizeof(float)));
}
BENCHMARK(BM_CacheRead)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
