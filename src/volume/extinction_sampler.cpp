#include "volume/extinction_sampler.h"

#include <array>
#include <cmath>

namespace nph::scene {

double ExtinctionSampler::fetch(const std::vector<float>& a, int i, int j, int k) const {
  if (i < 0 || j < 0 || k < 0 || i >= v_.nx || j >= v_.ny || k >= v_.nz) return 0.0;
  return double(a[v_.index(i, j, k)]);
}

ExtinctionSample ExtinctionSampler::at(const glm::dvec3& world_m) const {
  const glm::dvec3 g = f_.gridFromWorld(world_m);
  ExtinctionSample s;
  const double reach = reachVoxels(r_);
  if (!(g.x >= -reach && g.y >= -reach && g.z >= -reach && g.x <= v_.nx + reach && g.y <= v_.ny + reach &&
        g.z <= v_.nz + reach)) {
    return s;  // outside (β = 0 there) or NaN
  }
  const glm::dvec3 c = g - 0.5;  // continuous index relative to voxel centres
  const glm::dvec3 fl = glm::floor(c);
  const glm::dvec3 t = c - fl;
  const glm::ivec3 i0(fl);
  if (r_ == Reconstruction::Cubic) {
    // Voxels i0 − 1 … i0 + 2 per axis with the B-spline weights of the fractions t.
    const std::array<double, 4> wx = cubicBSplineWeights(t.x), wy = cubicBSplineWeights(t.y),
                                wz = cubicBSplineWeights(t.z);
    auto tricubic = [&](const std::vector<float>& a) {
      if (a.empty()) return 0.0;
      double r = 0.0;
      for (int dz = 0; dz < 4; ++dz)
        for (int dy = 0; dy < 4; ++dy) {
          const double wyz = wy[std::size_t(dy)] * wz[std::size_t(dz)];
          for (int dx = 0; dx < 4; ++dx) {
            r += wx[std::size_t(dx)] * wyz * fetch(a, i0.x - 1 + dx, i0.y - 1 + dy, i0.z - 1 + dz);
          }
        }
      return r;
    };
    s.ice_per_m = tricubic(v_.ice_per_m);
    s.water_per_m = tricubic(v_.water_per_m);
    return s;
  }
  auto trilinear = [&](const std::vector<float>& a) {
    if (a.empty()) return 0.0;
    double r = 0.0;
    for (int dz = 0; dz < 2; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const double wgt = (dx ? t.x : 1.0 - t.x) * (dy ? t.y : 1.0 - t.y) * (dz ? t.z : 1.0 - t.z);
          if (wgt != 0.0) r += wgt * fetch(a, i0.x + dx, i0.y + dy, i0.z + dz);
        }
    return r;
  };
  s.ice_per_m = trilinear(v_.ice_per_m);
  s.water_per_m = trilinear(v_.water_per_m);
  return s;
}

}  // namespace nph::scene
