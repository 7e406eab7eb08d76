#include "accuracy/accuracy_scenes.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "io/model_file.h"
#include "physics/volume_builder.h"
#include "presets.h"

namespace nph::accuracy {
namespace {

ExtinctionVolumes emptyBox(int nx, int ny, int nz, double dx_m, double dz_m, double z_bottom_m) {
  return ExtinctionVolumes::zeros(nx, ny, nz, dx_m, dz_m, z_bottom_m);
}

// Smooth 2-D value noise in [0, 1]: a seeded random lattice of `cells`² values, bicubic-smoothed
// (smoothstep weights), periodic. Octaves add detail at half the amplitude each.
class ValueNoise {
 public:
  ValueNoise(int cells, unsigned seed) : n_(cells), v_(std::size_t(cells) * std::size_t(cells)) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (double& x : v_) x = u(rng);
  }
  /// (x, y) in [0, 1)²
  double at(double x, double y) const {
    const double fx = x * n_, fy = y * n_;
    const int i = int(std::floor(fx)), j = int(std::floor(fy));
    const double tx = smooth(fx - i), ty = smooth(fy - j);
    auto v = [&](int a, int b) { return v_[std::size_t(wrap(b)) * std::size_t(n_) + std::size_t(wrap(a))]; };
    const double a = v(i, j) + tx * (v(i + 1, j) - v(i, j));
    const double b = v(i, j + 1) + tx * (v(i + 1, j + 1) - v(i, j + 1));
    return a + ty * (b - a);
  }
  double fractal(double x, double y, int octaves) const {
    double sum = 0.0, amp = 1.0, norm = 0.0;
    for (int o = 0; o < octaves; ++o) {
      sum += amp * at(std::fmod(x * (1 << o) + 0.37 * o, 1.0), std::fmod(y * (1 << o) + 0.61 * o, 1.0));
      norm += amp;
      amp *= 0.5;
    }
    return sum / norm;
  }

 private:
  static double smooth(double t) { return t * t * (3.0 - 2.0 * t); }
  int wrap(int a) const { return ((a % n_) + n_) % n_; }
  int n_;
  std::vector<double> v_;
};

// Camera looking at `target` from compass azimuth `azimuth_deg` (direction from the target to the
// camera), `elevation_deg` above the horizon, at `distance_m`.
scene::Camera orbit(const glm::dvec3& target, double azimuth_deg, double elevation_deg, double distance_m,
                    double fov_deg, int width, int height) {
  const double az = glm::radians(azimuth_deg), el = glm::radians(elevation_deg);
  scene::Camera c;
  c.target_m = target;
  c.position_m =
      target + distance_m * glm::dvec3(std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el));
  c.up = elevation_deg > 89.0 ? glm::dvec3(0.0, 1.0, 0.0) : glm::dvec3(0.0, 0.0, 1.0);
  c.vertical_fov_deg = fov_deg;
  c.width = width;
  c.height = height;
  return c;
}

ExtinctionVolumes generatedHurricane(bool quick, const std::string& scratch_dir) {
  datagen::WrfHurricaneSpec spec = datagen::wrfPreset(datagen::SampleSize::Tiny);
  if (!quick) {
    spec.nx = 96;
    spec.ny = 96;
    spec.nz = 30;
    spec.dx_m = 7000.0;  // 672 km: storm, eye and rainbands
  }
  spec.ntimes = 1;
  std::filesystem::create_directories(scratch_dir);
  const std::string path =
      (std::filesystem::path(scratch_dir) / (quick ? "wrfout_quick.nc" : "wrfout_accuracy.nc")).string();
  datagen::writeWrfHurricane(spec, path);
  const auto file = io::openModelFile(path);
  ExtinctionVolumes v =
      physics::buildExtinctionVolumes(file.load(0), physics::defaultOptics(), physics::VerticalGridOptions{});
  v.source_file = "generated hurricane";
  return v;
}

}  // namespace

ExtinctionVolumes stratusDeck(int n, unsigned seed) {
  // Stratocumulus: 1 km cells, base 900 m, top 1150-1500 m, adiabatic-like β rising with height
  // above base to ≈ 0.05 /m at the top (liquid water ≈ 0.3-0.5 g/m³, r_eff ≈ 10 µm), broken
  // where the noise is low.
  ExtinctionVolumes v = emptyBox(n, n, 14, 1000.0, 50.0, 800.0);
  const ValueNoise noise(8, seed), holes(16, seed + 1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = (i + 0.5) / n, y = (j + 0.5) / n;
      const double top = 1150.0 + 350.0 * noise.fractal(x, y, 3);
      const double cover = std::clamp((holes.fractal(x, y, 2) - 0.3) / 0.15, 0.0, 1.0);
      for (int k = 0; k < v.nz; ++k) {
        const double z = v.layerCentreHeight_m(k);
        if (z < 900.0 || z > top) continue;
        v.water_per_m[v.index(i, j, k)] = float(cover * 0.05 * (z - 900.0) / (top - 900.0));
      }
    }
  v.updateMaxima();
  return v;
}

ExtinctionVolumes cumulusField(int n, unsigned seed) {
  // Fair-weather cumuli: 250 m cells, base 1000 m, towers 0.8-2.5 km tall, β ≈ 0.03 /m in the
  // cores tapering to the edges (τ through a core ≈ 30), tops of ice above 4 km.
  ExtinctionVolumes v = emptyBox(n, n, 40, 250.0, 125.0, 500.0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double side = n * 250.0;
  const int clouds = std::max(4, n * n / 400);
  const ValueNoise lumps(12, seed + 7);
  for (int c = 0; c < clouds; ++c) {
    const double cx = u(rng) * side, cy = u(rng) * side;
    const double radius = 500.0 + 1200.0 * u(rng);
    const double height = 800.0 + 1700.0 * u(rng) * u(rng) * 1.5;
    for (int k = 0; k < v.nz; ++k) {
      const double z = v.layerCentreHeight_m(k);
      const double h = (z - 1000.0) / height;  // 0 at base, 1 at top
      if (h < 0.0 || h > 1.0) continue;
      const double rAt = radius * (0.6 + 0.4 * std::sin(std::acos(std::clamp(2.0 * h - 1.0, -1.0, 1.0))));
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const double dx = (i + 0.5) * 250.0 - cx, dy = (j + 0.5) * 250.0 - cy;
          const double r = std::sqrt(dx * dx + dy * dy) / rAt;
          const double wobble = 0.75 + 0.5 * lumps.at((i + 0.5) / n, std::fmod((j + 0.5) / n + 0.13 * k / v.nz, 1.0));
          if (r * wobble >= 1.0) continue;
          const float b = float(0.03 * (1.0 - r * r * wobble * wobble) * std::min(1.0, 4.0 * h + 0.3));
          const std::size_t idx = v.index(i, j, k);
          if (z > 4000.0) {
            v.ice_per_m[idx] = std::max(v.ice_per_m[idx], 0.3f * b);
          } else {
            v.water_per_m[idx] = std::max(v.water_per_m[idx], b);
          }
        }
    }
  }
  v.updateMaxima();
  return v;
}

ExtinctionVolumes cirrusLayer(int n, unsigned seed) {
  // Cirrus: 1 km cells, ice between 8.7 and 10.2 km, β_ice ≤ 4e-4 /m in streaks (τ ≈ 0.05-0.6).
  ExtinctionVolumes v = emptyBox(n, n, 10, 1000.0, 150.0, 8700.0);
  const ValueNoise noise(6, seed), streak(24, seed + 3);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = (i + 0.5) / n, y = (j + 0.5) / n;
      const double amount = std::clamp(1.6 * noise.fractal(x, y, 3) - 0.45, 0.0, 1.0) *
                            (0.5 + 0.5 * streak.at(std::fmod(x + 0.3 * y, 1.0), std::fmod(0.2 * y, 1.0)));
      for (int k = 1; k < v.nz - 1; ++k) {
        const double shape = std::sin(3.14159265358979 * (k - 0.5) / (v.nz - 2));
        v.ice_per_m[v.index(i, j, k)] = float(4e-4 * amount * shape);
      }
    }
  v.updateMaxima();
  return v;
}

SceneSet standardScenes(int width, int height, bool quick, const std::string& scratch_dir) {
  SceneSet set;
  set.volumes.reserve(4);
  set.volumes.push_back(generatedHurricane(quick, scratch_dir));
  set.volumes.push_back(stratusDeck(quick ? 32 : 96, 11));
  set.volumes.push_back(cumulusField(quick ? 32 : 96, 21));
  set.volumes.push_back(cirrusLayer(quick ? 32 : 96, 31));
  const char* names[] = {"hurricane", "stratus", "cumulus", "cirrus"};
  const double exaggeration[] = {8.0, 4.0, 1.0, 4.0};
  auto add = [&](int vi, const std::string& view, double camAz, double camEl, double dist, double fov, double sunAz,
                 double sunEl) {
    AccuracyScene s;
    s.volume_name = names[vi];
    s.name = std::string(names[vi]) + "-" + view;
    s.volumes = &set.volumes[std::size_t(vi)];
    s.frame = volume::frameOf(*s.volumes, exaggeration[vi]);
    const glm::dvec3 size = s.frame.size_m();
    const glm::dvec3 centre = s.frame.min_m() + 0.5 * size;
    s.camera = orbit(centre, camAz, camEl, dist * std::max(size.x, size.y), fov, width, height);
    s.sun.azimuth_deg = sunAz;
    s.sun.elevation_deg = sunEl;
    set.scenes.push_back(s);
  };
  // name, camera azimuth/elevation/distance (× domain side)/fov, sun azimuth/elevation
  add(0, "above-sun-high", 0.0, 90.0, 1.9, 30.0, 120.0, 70.0);
  add(0, "oblique-sun-low", 190.0, 35.0, 1.3, 40.0, 300.0, 12.0);
  add(0, "oblique-sun-behind", 190.0, 35.0, 1.3, 40.0, 190.0, 30.0);
  add(1, "sun-low", 160.0, 30.0, 1.2, 40.0, 60.0, 15.0);
  add(2, "sun-high", 200.0, 40.0, 1.4, 40.0, 250.0, 65.0);
  add(2, "sun-behind", 200.0, 40.0, 1.4, 40.0, 200.0, 35.0);
  add(3, "sun-low", 180.0, 25.0, 1.2, 45.0, 0.0, 10.0);
  // Golden hour (the sun 5° high, from the side of the view): towers lit through their sides.
  add(0, "golden-hour", 190.0, 35.0, 1.3, 40.0, 270.0, 5.0);
  add(2, "golden-hour", 200.0, 40.0, 1.4, 40.0, 290.0, 5.0);
  return set;
}

}  // namespace nph::accuracy
