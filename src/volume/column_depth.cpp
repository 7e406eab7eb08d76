#include "volume/column_depth.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/packing.hpp>

namespace nph {
namespace {
// The value the GPU stores: half precision (RG16F), clamped to the largest finite half.
float asHalf(double x) { return glm::unpackHalf1x16(glm::packHalf1x16(float(std::min(x, 65504.0)))); }
}  // namespace

ColumnDepths columnDepths(const ExtinctionVolumes& v) {
  ColumnDepths d;
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
  const glm::dvec3 g = frame.gridFromWorld(world_m) - 0.5;  // voxel centres at integers
  const glm::ivec3 n(d.nx, d.ny, d.nz);
  glm::dvec3 lo = glm::floor(g);
  const glm::dvec3 f = g - lo;
  glm::dvec2 out(0.0);
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 o(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    const glm::ivec3 idx = glm::clamp(glm::ivec3(lo) + o, glm::ivec3(0), n - 1);
    const double w = (o.x ? f.x : 1.0 - f.x) * (o.y ? f.y : 1.0 - f.y) * (o.z ? f.z : 1.0 - f.z);
    const std::size_t k =
        (std::size_t(idx.z) * std::size_t(d.ny) + std::size_t(idx.y)) * std::size_t(d.nx) + std::size_t(idx.x);
    out += w * glm::dvec2(d.up[k], d.down[k]);
  }
  return out;
}

}  // namespace nph
