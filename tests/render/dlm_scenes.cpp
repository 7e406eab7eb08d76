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

geo::GridGeoreference refinedGeoreference(const geo::GridGeoreference& g, int factor) {
  geo::GridGeoreference r = g;
  r.dx_m = g.dx_m / factor;
  r.dy_m = g.dy_m / factor;
  r.x0 = g.x0 - 0.5 * g.dx_m + 0.5 * r.dx_m;  // the same outer faces: the first fine centre ½ fine cell in
  r.y0 = g.y0 - 0.5 * g.dy_m + 0.5 * r.dy_m;
  r.lat_deg.clear();  // per-point lon/lat belong to the coarse grid
  r.lon_deg.clear();
  return r;
}

ExtinctionVolumes analyticStorm(const ExtinctionVolumes& like, int factor) {
  ExtinctionVolumes v = ExtinctionVolumes::zeros(like.nx * factor, like.ny * factor, like.nz, like.georef.dx_m / factor,
                                                 like.dz_m, like.z_bottom_m);
  v.georef = refinedGeoreference(like.georef, factor);
  // Cells in coarse-column units from the domain's corner: centre, σ_h, height of the core, β at
  // the core. Drawn once from a fixed seed, so every run and both resolutions see the same storm.
  struct Cell {
    double x, y, sigma, zc_m, beta;
  };
  std::vector<Cell> cells;
  std::mt19937 rng(1303u);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int c = 0; c < 40; ++c) {
    cells.push_back({like.nx * (0.15 + 0.7 * u(rng)), like.ny * (0.15 + 0.7 * u(rng)), 1.0 + 1.0 * u(rng),
                     3500.0 + 3000.0 * u(rng), 0.01 + 0.02 * u(rng)});
  }
  const double cx = 0.5 * like.nx, cy = 0.5 * like.ny, shield_sigma = 0.22 * std::min(like.nx, like.ny);
  for (int k = 0; k < v.nz; ++k) {
    const double z = v.layerCentreHeight_m(k);
    const double iceShare = std::clamp((z - 5000.0) / 3000.0, 0.0, 1.0);
    const double shieldZ = std::exp(-0.5 * std::pow((z - 7500.0) / 900.0, 2.0));
    for (int j = 0; j < v.ny; ++j) {
      for (int i = 0; i < v.nx; ++i) {
        const double x = (i + 0.5) / factor, y = (j + 0.5) / factor;  // in coarse columns
        double beta = 0.0005 * shieldZ *
                      std::exp(-0.5 * ((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (shield_sigma * shield_sigma));
        for (const Cell& c : cells) {
          const double r2 = ((x - c.x) * (x - c.x) + (y - c.y) * (y - c.y)) / (c.sigma * c.sigma);
          beta += c.beta * std::exp(-0.5 * r2 - 0.5 * std::pow((z - c.zc_m) / 2500.0, 2.0));
        }
        const std::size_t n = v.index(i, j, k);
        v.ice_per_m[n] = float(beta * iceShare);
        v.water_per_m[n] = float(beta * (1.0 - iceShare));
      }
    }
  }
  v.updateMaxima();
  return v;
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
