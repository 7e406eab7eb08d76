#include "dlm_scenes.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include <unistd.h>

#include "io/model_file.h"
#include "physics/volume_builder.h"
#include "presets.h"
#include "support/scratch_dir.h"

namespace nph::test {
namespace {

ExtinctionVolumes box(int nx, int ny, int nz) { return ExtinctionVolumes::zeros(nx, ny, nz, 3000.0, 250.0, 0.0); }

ExtinctionVolumes convert(const std::string& path) {
  const auto file = io::openModelFile(path);
  return physics::buildExtinctionVolumes(file.load(file.timesteps().size() > 3 ? 3 : 0), physics::defaultOptics(),
                                         physics::VerticalGridOptions{});
}

/// `name` in this process's scratch folder (removed at exit).
std::string tempPath(const std::string& name) {
  static const test::ScratchDir dir = test::ScratchDir::forProcess("dlm");
  return dir.file(name);
}

}  // namespace

ExtinctionVolumes homogeneousSlab(int nx, int ny, int nz, float beta) {
  ExtinctionVolumes v = box(nx, ny, nz);
  std::fill(v.water_per_m.begin(), v.water_per_m.end(), beta);
  v.updateMaxima();
  return v;
}

ExtinctionVolumes noisyVolume(int nx, int ny, int nz, unsigned seed) {
  ExtinctionVolumes v = box(nx, ny, nz);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 5e-3f);
  for (std::size_t i = 0; i < v.voxelCount(); ++i) {
    v.water_per_m[i] = u(rng);
    v.ice_per_m[i] = (i % 3 == 0) ? u(rng) : 0.0f;
  }
  v.updateMaxima();
  return v;
}

ExtinctionVolumes generatedHurricane(int) {
  const std::string path = tempPath("wrfout_tiny.nc");
  datagen::writeWrfHurricane(datagen::wrfPreset(datagen::SampleSize::Tiny), path);
  return convert(path);
}

ExtinctionVolumes coarseStorm() {
  const std::string path = tempPath("wrfout_coarse_storm.nc");
  datagen::WrfHurricaneSpec spec = datagen::coarseStormSpec();
  spec.ntimes = 1;
  datagen::writeWrfHurricane(spec, path);
  return convert(path);
}

LayerDifference layerDifference(const scene::RgbaImage& a, const scene::RgbaImage& b) {
  LayerDifference d;
  for (std::size_t i = 0; i < b.rgba.size(); ++i) {
    const double e = std::abs(double(a.rgba[i]) - double(b.rgba[i]));
    d.max = std::max(d.max, e);
    d.mean += e;
    if (i % 4 == 3) d.coverage += double(b.rgba[i]);
  }
  d.mean /= double(b.rgba.size());
  d.coverage /= double(b.rgba.size() / 4);
  return d;
}

LevelDifference levelDifference(const scene::RgbaImage& a, const scene::RgbaImage& b) {
  scene::ImageOutputOptions o;
  o.exposure_ev = scene::kDefaultExposureEv;
  const auto ca = scene::encodeSrgb8(a, o), cb = scene::encodeSrgb8(b, o);
  LevelDifference l;
  std::size_t n = 0;
  for (std::size_t i = 0; i < ca.size() && i < cb.size(); ++i) {
    const int d = std::abs(int(ca[i]) - int(cb[i]));
    l.max = std::max(l.max, d);
    n += d > 0;
  }
  l.differing = ca.empty() ? 0.0 : double(n) / double(ca.size());
  return l;
}

ExtinctionVolumes generatedIconScene() {
  const std::string path = tempPath("icon_tiny.nc");
  datagen::writeIconScene(datagen::iconPreset(datagen::SampleSize::Tiny, false), path);
  return convert(path);
}

}  // namespace nph::test
