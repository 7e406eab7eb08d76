#include "volume/column_depth.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/gtc/packing.hpp>

namespace nph {
namespace {
// The value the GPU stores: half precision (RG16F), clamped to the largest finite half.
float asHalf(double x) { return glm::unpackHalf1x16(glm::packHalf1x16(float(std::min(x, 65504.0)))); }
}  // namespace

ColumnDepths columnDepths(const ExtinctionVolumes& v, scene::Reconstruction reconstruction) {
  ColumnDepths d;
  d.reconstruction = reconstruction;
  d.nx = v.nx;
  d.ny = v.ny;
  d.nz = v.nz;
  d.up.assign(v.voxelCount(), 0.0f);
  d.down.assign(v.voxelCount(), 0.0f);
  auto beta = [&](std::size_t i) {
    double b = 0.0;
    if (i < v.ice_per_m.size()) b += double(v.ice_per_m[i]);
    if (i < v.water_per_m.size()) b += double(v.water_per_m[i]);
    return b;
  };
  for (int j = 0; j < v.ny; ++j) {
    for (int i = 0; i < v.nx; ++i) {
      double acc = 0.0;  // double: a column of 100 layers of small β keeps its sum
      for (int k = v.nz - 1; k >= 0; --k) {
        const double half = 0.5 * beta(v.index(i, j, k)) * v.dz_m;
        d.up[v.index(i, j, k)] = asHalf(acc + half);
        acc += 2.0 * half;
      }
      acc = 0.0;
      for (int k = 0; k < v.nz; ++k) {
        const double half = 0.5 * beta(v.index(i, j, k)) * v.dz_m;
        d.down[v.index(i, j, k)] = asHalf(acc + half);
        acc += 2.0 * half;
      }
    }
  }
  return d;
}

glm::dvec2 columnDepthAt(const ColumnDepths& d, const scene::VolumeFrame& frame, const glm::dvec3& world_m) {
  if (d.nx <= 0 || d.ny <= 0 || d.nz <= 0) return glm::dvec2(0.0);
  // The extinction's own filter (volume/reconstruction.h), clamped to the edge (see the header).
  const glm::ivec3 last(d.nx - 1, d.ny - 1, d.nz - 1);
  return scene::reconstructAt(d.reconstruction, frame.gridFromWorld(world_m) - 0.5, [&](int i, int j, int k) {
    const glm::ivec3 idx = glm::clamp(glm::ivec3(i, j, k), glm::ivec3(0), last);
    const std::size_t n =
        (std::size_t(idx.z) * std::size_t(d.ny) + std::size_t(idx.y)) * std::size_t(d.nx) + std::size_t(idx.x);
    return glm::dvec2(d.up[n], d.down[n]);
  });
}

}  // namespace nph
