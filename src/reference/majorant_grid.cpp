#include "reference/majorant_grid.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace nph::reference {

MajorantGrid::MajorantGrid(const ExtinctionField& field, int brick_voxels) : field_(field), brick_(brick_voxels) {
  if (brick_voxels < 1) throw UsageError("MajorantGrid: brick size must be at least 1 voxel");
  const ExtinctionVolumes& v = field.volumes();
  // Per-voxel total β, validated; the interpolating spline's coefficients may be negative
  // (volume/spline_coefficients.h): their positive parts bound β_ice⁺ + β_water⁺ as the voxels do.
  const bool coefficients = volume::readsSplineCoefficients(field.reconstruction());
  std::vector<double> total(v.voxelCount(), 0.0);
  for (const std::vector<float>* a : {&v.ice_per_m, &v.water_per_m}) {
    if (a->empty()) continue;
    for (std::size_t i = 0; i < total.size(); ++i) {
      const float x = (*a)[i];
      if (!std::isfinite(x) || (x < 0.0f && !coefficients)) {
        throw InputError("MajorantGrid: " + std::string(a == &v.ice_per_m ? "ice_per_m" : "water_per_m") + " voxel " +
                         std::to_string(i) + " is " + std::to_string(x) + ", expected a finite extinction >= 0 1/m");
      }
      total[i] += std::max(double(x), 0.0);
    }
  }
  const glm::ivec3 n{v.nx, v.ny, v.nz};
  bricks_ = (n + brick_ - 1) / brick_;
  // Separable max: first the max over each brick's (extended) x range, then y, then z. The range
  // grows by the filter's reach (volume/reconstruction.h): a point of the brick reads voxels
  // bB − R … (b+1)B − 1 + R.
  const int reach = volume::reachVoxels(field.reconstruction());
  auto range = [&](int brick, int axis, int& lo, int& hi) {
    lo = std::max(0, brick * brick_ - reach);
    hi = std::min(n[axis] - 1, (brick + 1) * brick_ - 1 + reach);
  };
  std::vector<double> mx(std::size_t(bricks_.x) * std::size_t(v.ny) * std::size_t(v.nz), 0.0);
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int bx = 0; bx < bricks_.x; ++bx) {
        int lo = 0, hi = 0;
        range(bx, 0, lo, hi);
        double m = 0.0;
        for (int i = lo; i <= hi; ++i) m = std::max(m, total[v.index(i, j, k)]);
        mx[(std::size_t(k) * std::size_t(v.ny) + std::size_t(j)) * std::size_t(bricks_.x) + std::size_t(bx)] = m;
      }
  std::vector<double> my(std::size_t(bricks_.x) * std::size_t(bricks_.y) * std::size_t(v.nz), 0.0);
  for (int k = 0; k < v.nz; ++k)
    for (int by = 0; by < bricks_.y; ++by)
      for (int bx = 0; bx < bricks_.x; ++bx) {
        int lo = 0, hi = 0;
        range(by, 1, lo, hi);
        double m = 0.0;
        for (int j = lo; j <= hi; ++j)
          m = std::max(
              m, mx[(std::size_t(k) * std::size_t(v.ny) + std::size_t(j)) * std::size_t(bricks_.x) + std::size_t(bx)]);
        my[(std::size_t(k) * std::size_t(bricks_.y) + std::size_t(by)) * std::size_t(bricks_.x) + std::size_t(bx)] = m;
      }
  majorant_.assign(std::size_t(bricks_.x) * std::size_t(bricks_.y) * std::size_t(bricks_.z), 0.0);
  for (int bz = 0; bz < bricks_.z; ++bz)
    for (int by = 0; by < bricks_.y; ++by)
      for (int bx = 0; bx < bricks_.x; ++bx) {
        int lo = 0, hi = 0;
        range(bz, 2, lo, hi);
        double m = 0.0;
        for (int k = lo; k <= hi; ++k)
          m = std::max(m, my[(std::size_t(k) * std::size_t(bricks_.y) + std::size_t(by)) * std::size_t(bricks_.x) +
                             std::size_t(bx)]);
        // Round up by a few ulps so float→double interpolation rounding can never exceed μ̄.
        majorant_[(std::size_t(bz) * std::size_t(bricks_.y) + std::size_t(by)) * std::size_t(bricks_.x) +
                  std::size_t(bx)] = m * (1.0 + 1e-12);
      }
}

double MajorantGrid::majorantAt(const glm::dvec3& world_m) const {
  const glm::dvec3 g = field_.frame().gridFromWorld(world_m);
  const glm::dvec3 n(field_.frame().voxels);
  const double s = volume::supportVoxels(field_.reconstruction());
  if (!(g.x >= -s && g.y >= -s && g.z >= -s && g.x <= n.x + s && g.y <= n.y + s && g.z <= n.z + s)) {
    return 0.0;
  }
  const glm::ivec3 b = glm::clamp(glm::ivec3(glm::floor(g / double(brick_))), glm::ivec3(0), bricks_ - 1);
  return majorant(b.x, b.y, b.z);
}

}  // namespace nph::reference
