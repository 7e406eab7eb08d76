#include "volume/occupancy.h"

#include <algorithm>

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
  std::vector<float> scratch;
  OccupancyGrid g;
  g.brick = brick;
  const int d = reachVoxels(reconstruction) + extra_reach_voxels;
  g.dilation_voxels = d;
  g.bricks = {(v.nx + brick - 1) / brick, (v.ny + brick - 1) / brick, (v.nz + brick - 1) / brick};
  g.max_per_m.assign(std::size_t(g.bricks.x) * std::size_t(g.bricks.y) * std::size_t(g.bricks.z), 0.0f);
  g.nonEmptyMinVoxel = {v.nx, v.ny, v.nz};
  g.nonEmptyMaxVoxel = {-1, -1, -1};
  for (int k = 0; k < v.nz; ++k) {
    const ExtinctionSlices::Slice s = slices.slice(k, scratch);  // an absent phase reads 0: the same sum
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i) {
        const std::size_t idx = std::size_t(j) * std::size_t(v.nx) + std::size_t(i);
        // Positive parts: β_ice⁺ + β_water⁺ ≤ Σw·(c_ice⁺ + c_water⁺) also where the interpolating
        // spline's coefficients are negative (volume/spline_coefficients.h); the voxels' sum otherwise.
        const float b = (std::max(s.ice[idx], 0.0f) + std::max(s.water[idx], 0.0f)) * max_scale;
        if (!(b > 0.0f)) continue;  // also skips NaN (the loaders never produce it)
        g.nonEmptyMinVoxel = glm::min(g.nonEmptyMinVoxel, glm::ivec3(i, j, k));
        g.nonEmptyMaxVoxel = glm::max(g.nonEmptyMaxVoxel, glm::ivec3(i, j, k));
        // Dilate by the reach d: every brick whose voxels, grown by d, contain (i, j, k).
        const glm::ivec3 lo = glm::max(glm::ivec3(i - d, j - d, k - d), glm::ivec3(0)) / brick;
        const glm::ivec3 hi = glm::min(glm::ivec3(i + d, j + d, k + d), glm::ivec3(v.nx, v.ny, v.nz) - 1) / brick;
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
  return g;
}

}  // namespace nph::volume
