#include "volume/occupancy.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/error.h"

#include "volume/spline_coefficients.h"

namespace nph::volume {

OccupancyGrid buildOccupancy(const ExtinctionVolumes& v, int brick, Reconstruction reconstruction,
                             int extra_reach_voxels, float max_scale) {
  if (readsSplineCoefficients(reconstruction))  // the bound is the largest coefficient in reach
    return buildOccupancy(VolumeSlices(std::make_shared<const ExtinctionVolumes>(splineCoefficientVolumes(v))), brick,
                          reconstruction, extra_reach_voxels, max_scale);
  return buildOccupancy(VolumeSlices(v), brick, reconstruction, extra_reach_voxels, max_scale);
}

OccupancyGrid buildOccupancy(const ExtinctionSlices& slices, int brick, Reconstruction reconstruction,
                             int extra_reach_voxels, float max_scale) {
  const ExtinctionVolumes& v = slices.volumes();
  OccupancyBuilder b(v, brick, reconstruction, extra_reach_voxels, max_scale);
  std::vector<float> scratch;
  for (int k = 0; k < v.nz; ++k) b.add(k, slices.slice(k, scratch));  // an absent phase reads 0: the same sum
  return b.finish();
}

OccupancyBuilder::OccupancyBuilder(const ExtinctionVolumes& v, int brick, Reconstruction reconstruction,
                                   int extra_reach_voxels, float max_scale)
    : n_(v.nx, v.ny, v.nz),
      reconstruction_(reconstruction),
      extra_reach_voxels_(extra_reach_voxels),
      max_scale_(max_scale) {
  OccupancyGrid& g = g_;
  g.brick = brick;
  g.dilation_voxels = reachVoxels(reconstruction) + extra_reach_voxels;
  g.bricks = {(v.nx + brick - 1) / brick, (v.ny + brick - 1) / brick, (v.nz + brick - 1) / brick};
  g.max_per_m.assign(std::size_t(g.bricks.x) * std::size_t(g.bricks.y) * std::size_t(g.bricks.z), 0.0f);
  own_min_.assign(g.max_per_m.size(), std::numeric_limits<float>::infinity());
  g.nonEmptyMinVoxel = {v.nx, v.ny, v.nz};
  g.nonEmptyMaxVoxel = {-1, -1, -1};
}

void OccupancyBuilder::add(int k, const ExtinctionSlices::Slice& s) {
  if (k != next_k_ || k >= n_.z)
    throw UsageError(fmt::format("OccupancyBuilder::add: layer {} given, {} is next", k, next_k_));
  ++next_k_;
  OccupancyGrid& g = g_;
  const int brick = g.brick, d = g.dilation_voxels;
  for (int j = 0; j < n_.y; ++j)
    for (int i = 0; i < n_.x; ++i) {
      const std::size_t idx = std::size_t(j) * std::size_t(n_.x) + std::size_t(i);
      // Positive parts: β_ice⁺ + β_water⁺ ≤ Σw·(c_ice⁺ + c_water⁺) also where the interpolating
      // spline's coefficients are negative (volume/spline_coefficients.h); the voxels' sum otherwise.
      const float b = (std::max(s.ice[idx], 0.0f) + std::max(s.water[idx], 0.0f)) * max_scale_;
      float& own = own_min_[(std::size_t(k / brick) * std::size_t(g.bricks.y) + std::size_t(j / brick)) *
                                std::size_t(g.bricks.x) +
                            std::size_t(i / brick)];
      own = std::min(own, std::isnan(b) ? 0.0f : b);
      if (!(b > 0.0f)) continue;  // also skips NaN (the loaders never produce it)
      g.nonEmptyMinVoxel = glm::min(g.nonEmptyMinVoxel, glm::ivec3(i, j, k));
      g.nonEmptyMaxVoxel = glm::max(g.nonEmptyMaxVoxel, glm::ivec3(i, j, k));
      // Dilate by the reach d: every brick whose voxels, grown by d, contain (i, j, k).
      const glm::ivec3 lo = glm::max(glm::ivec3(i - d, j - d, k - d), glm::ivec3(0)) / brick;
      const glm::ivec3 hi = glm::min(glm::ivec3(i + d, j + d, k + d), n_ - 1) / brick;
      for (int bk = lo.z; bk <= hi.z; ++bk)
        for (int bj = lo.y; bj <= hi.y; ++bj)
          for (int bi = lo.x; bi <= hi.x; ++bi) {
            float& m =
                g.max_per_m[(std::size_t(bk) * std::size_t(g.bricks.y) + std::size_t(bj)) * std::size_t(g.bricks.x) +
                            std::size_t(bi)];
            m = std::max(m, b);
          }
    }
}

OccupancyGrid OccupancyBuilder::finish() {
  if (next_k_ != n_.z) throw UsageError(fmt::format("OccupancyBuilder::finish: {} of {} layers added", next_k_, n_.z));
  OccupancyGrid& g = g_;
  const std::vector<float>& own_min = own_min_;
  const int brick = g.brick;
  // The lower bound: the least of the brick's and its 26 neighbours' own minima (a neighbour past
  // the grid's edge is the zero border), valid for a reach up to one brick with non-negative
  // weights; 0 for the filters and detail where it is not (occupancy.h).
  g.min_per_m.assign(g.max_per_m.size(), 0.0f);
  const bool bounded = !readsSplineCoefficients(reconstruction_) && extra_reach_voxels_ == 0 && max_scale_ == 1.0f &&
                       reachVoxels(reconstruction_) <= brick;
  if (!bounded) return std::move(g);
  const glm::ivec3 nb = g.bricks;
  auto index = [&](int i, int j, int k) {
    return (std::size_t(k) * std::size_t(nb.y) + std::size_t(j)) * std::size_t(nb.x) + std::size_t(i);
  };
  for (int k = 0; k < nb.z; ++k)
    for (int j = 0; j < nb.y; ++j)
      for (int i = 0; i < nb.x; ++i) {
        float m = std::numeric_limits<float>::infinity();
        for (int dk = -1; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const int a = i + di, b = j + dj, c = k + dk;
              const bool inside = a >= 0 && b >= 0 && c >= 0 && a < nb.x && b < nb.y && c < nb.z;
              m = std::min(m, inside ? own_min[index(a, b, c)] : 0.0f);
            }
        g.min_per_m[index(i, j, k)] = m;
      }
  return std::move(g);
}

}  // namespace nph::volume
