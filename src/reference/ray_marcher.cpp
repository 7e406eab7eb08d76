#include "reference/ray_marcher.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "volume/extinction_sampler.h"

namespace nph::reference {
namespace {

double hg4pi(double cosPsi, double g) {
  const double g2 = g * g;
  return (1.0 - g2) / std::pow(std::max(1.0 + g2 - 2.0 * g * cosPsi, 1e-6), 1.5);
}

}  // namespace

scene::RgbaImage marchCloudLayer(const ExtinctionVolumes& volumes, const scene::VolumeFrame& frame,
                                 const scene::Camera& camera, const scene::Sun& sun,
                                 const std::function<double(const glm::dvec3&)>& sunlightAt,
                                 const RayMarchSettings& s) {
  const scene::ExtinctionSampler sampler(volumes, frame);
  scene::RgbaImage img;
  img.width = camera.width;
  img.height = camera.height;
  img.rgba.assign(std::size_t(img.width) * std::size_t(img.height) * 4, 0.0f);
  const glm::dvec3 voxel = frame.voxel_size_m;
  const double step = s.step_voxels * std::min({voxel.x, voxel.y, voxel.z});
  const glm::dvec3 lo = frame.min_m() - voxel, hi = frame.max_m() + voxel;  // β is 0 beyond
  const glm::dvec3 lightDir = -sun.toSun();
  const glm::dvec3 sunRadiance = sun.colour * sun.intensity;
  const glm::dvec3 ambient = s.ambient * sun.intensity;
  tbb::parallel_for(0, img.height, [&](int y) {
    for (int x = 0; x < img.width; ++x) {
      const glm::dvec3 dir = camera.rayDirection(x + 0.5, y + 0.5);
      const glm::dvec3 o = camera.position_m;
      // Slab test against the grown box.
      double t0 = 0.0, t1 = 1e300;
      for (int a = 0; a < 3; ++a) {
        if (dir[a] == 0.0) {
          if (o[a] < lo[a] || o[a] > hi[a]) t1 = -1.0;
          continue;
        }
        double ta = (lo[a] - o[a]) / dir[a], tb = (hi[a] - o[a]) / dir[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
      }
      const double cosPsi = glm::dot(lightDir, -dir);
      const double pIce = hg4pi(cosPsi, s.g_ice), pWater = hg4pi(cosPsi, s.g_water);
      glm::dvec3 C(0.0);
      double T = 1.0;
      for (double t = t0 + 0.5 * step; t < t1 && T > s.min_transmittance; t += step) {
        const glm::dvec3 p = o + t * dir;
        const scene::ExtinctionSample b = sampler.at(p);
        const double bt = b.total();
        if (bt <= 0.0) continue;
        const double Ts = std::exp(-bt * step);
        const double phase = (b.ice_per_m * pIce + b.water_per_m * pWater) / bt;  // Nes eq. 5.12
        C += T * (1.0 - Ts) * (sunRadiance * sunlightAt(p) * phase + ambient);
        T *= Ts;
      }
      float* px = &img.rgba[(std::size_t(y) * std::size_t(img.width) + std::size_t(x)) * 4];
      px[0] = float(C.x);
      px[1] = float(C.y);
      px[2] = float(C.z);
      px[3] = float(1.0 - T);
    }
  });
  return img;
}

}  // namespace nph::reference
