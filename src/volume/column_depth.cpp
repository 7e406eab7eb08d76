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
  const glm::dvec3 g = frame.gridFromWorld(world_m) - 0.5;  // voxel centres at integers
  const glm::ivec3 n(d.nx, d.ny, d.nz);
  const glm::dvec3 lo = glm::floor(g);
  const glm::dvec3 f = g - lo;
  // Per axis the voxels lo + first … lo + first + taps − 1 with their filter weights: the hat's two
  // (trilinear) or the B-spline's four (cubic, volume/reconstruction.h).
  const bool cubic = d.reconstruction == scene::Reconstruction::Cubic;
  const int taps = cubic ? 4 : 2, first = cubic ? -1 : 0;
  std::array<std::array<double, 4>, 3> w{};
  for (int a = 0; a < 3; ++a)
    w[std::size_t(a)] = cubic ? scene::cubicBSplineWeights(f[a]) : std::array<double, 4>{1.0 - f[a], f[a], 0.0, 0.0};
  glm::dvec2 out(0.0);
  for (int cz = 0; cz < taps; ++cz) {
    for (int cy = 0; cy < taps; ++cy) {
      for (int cx = 0; cx < taps; ++cx) {
        const glm::ivec3 idx =
            glm::clamp(glm::ivec3(lo) + glm::ivec3(cx, cy, cz) + first, glm::ivec3(0), n - 1);  // clamp to edge
        const double wt = w[0][std::size_t(cx)] * w[1][std::size_t(cy)] * w[2][std::size_t(cz)];
        const std::size_t k =
            (std::size_t(idx.z) * std::size_t(d.ny) + std::size_t(idx.y)) * std::size_t(d.nx) + std::size_t(idx.x);
        out += wt * glm::dvec2(d.up[k], d.down[k]);
      }
    }
  }
  return out;
}

}  // namespace nph
