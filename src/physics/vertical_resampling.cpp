#include "physics/vertical_resampling.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/error.h"
#include "core/large_buffer.h"
#include "core/limits.h"
#include "physics/pchip.h"

namespace nph::physics {

namespace {

void requireHeights(const io::ModelTimestep& ts) {
  if (ts.height_m.size() != ts.voxelCount()) {
    throw InputError(fmt::format("{}: timestep {}: height has {} values, expected {} ({}x{}x{})", ts.source_file,
                                 ts.time_index, ts.height_m.size(), ts.voxelCount(), ts.nx, ts.ny, ts.nz));
  }
  const std::size_t columns = std::size_t(ts.nx) * std::size_t(ts.ny);
  if (!ts.terrain_height_m.empty() && ts.terrain_height_m.size() != columns) {
    throw InputError(fmt::format("{}: terrain height has {} values, expected {} ({}x{})", ts.source_file,
                                 ts.terrain_height_m.size(), columns, ts.nx, ts.ny));
  }
}

/// `levels` (a double from heights) as the grid's nz, range-checked before the cast against
/// limits::kMaxDerivedLevels: terrain of -1e7 m planned 40 026 levels, heights of 1e26 m
/// overflowed the int conversion (undefined behaviour).
int checkedLevels(const io::ModelTimestep& ts, const VerticalGrid& g, double levels, const char* up_to) {
  if (!(levels <= double(limits::kMaxDerivedLevels))) {
    throw InputError(fmt::format(
        "{}: timestep {}: the resampled grid from {} m up to {} would have {} levels of {} m, more than the "
        "limit of {} (limits::kMaxDerivedLevels); check the file's heights and terrain, or choose a larger "
        "dz / an explicit top",
        ts.source_file, ts.time_index, g.z_bottom_m, up_to, levels, g.dz_m, limits::kMaxDerivedLevels));
  }
  return static_cast<int>(levels);
}

double surfaceHeight(const io::ModelTimestep& ts, int i, int j) {
  if (!ts.terrain_height_m.empty()) {
    return double(ts.terrain_height_m[std::size_t(j) * std::size_t(ts.nx) + std::size_t(i)]);
  }
  const double h0 = double(ts.height_m[ts.index(i, j, 0)]);
  if (ts.nz < 2) return h0;
  return h0 - 0.5 * (double(ts.height_m[ts.index(i, j, 1)]) - h0);
}

/// Height above which column values are 0 (half a layer above the top mass level).
double columnTop(const std::vector<double>& h) {
  const std::size_t n = h.size();
  return n < 2 ? h[0] : h[n - 1] + 0.5 * (h[n - 1] - h[n - 2]);
}

}  // namespace

double defaultBottomHeight_m(const io::ModelTimestep& ts, double dz_m) {
  requireHeights(ts);
  double lowest = std::numeric_limits<double>::infinity();
  for (int j = 0; j < ts.ny; ++j) {
    for (int i = 0; i < ts.nx; ++i) lowest = std::min(lowest, surfaceHeight(ts, i, j));
  }
  if (!std::isfinite(lowest)) {
    throw InputError(fmt::format("{}: surface height is not finite", ts.source_file));
  }
  // Lower bound of real surfaces: the Dead Sea shore lies at -430 m; heights below -1 km are not
  // terrain (a -1e7 m terrain planned a 40 026-level grid).
  constexpr double kLowestSurface_m = -1000.0;
  if (lowest < kLowestSurface_m) {
    throw InputError(fmt::format("{}: timestep {}: surface height {} m, expected terrain above {} m", ts.source_file,
                                 ts.time_index, lowest, kLowestSurface_m));
  }
  return dz_m * std::floor(lowest / dz_m);
}

std::optional<double> condensateTopHeight_m(const io::ModelTimestep& ts, const ModelLevelExtinction& beta,
                                            double threshold) {
  requireHeights(ts);
  std::optional<double> top;
  for (int j = 0; j < ts.ny; ++j) {
    for (int i = 0; i < ts.nx; ++i) {
      for (int k = ts.nz - 1; k >= 0; --k) {
        const std::size_t m = ts.index(i, j, k);
        if (beta.ice_per_m[m] + beta.water_per_m[m] > float(threshold)) {
          double z;
          if (k + 1 < ts.nz) {
            z = double(ts.height_m[ts.index(i, j, k + 1)]);
          } else {
            const double h = double(ts.height_m[m]);
            z = ts.nz > 1 ? h + 0.5 * (h - double(ts.height_m[ts.index(i, j, k - 1)])) : h;
          }
          top = top ? std::max(*top, z) : z;
          break;
        }
      }
    }
  }
  return top;
}

VerticalGrid planVerticalGrid(const io::ModelTimestep& ts, const ModelLevelExtinction& beta,
                              const VerticalGridOptions& o) {
  if (!(o.dz_m > 0.0) || !std::isfinite(o.dz_m)) {
    throw UsageError(fmt::format("vertical spacing dz must be > 0 m, got {}", o.dz_m));
  }
  VerticalGrid g;
  g.dz_m = o.dz_m;
  g.z_bottom_m = o.z_bottom_m ? *o.z_bottom_m : defaultBottomHeight_m(ts, o.dz_m);
  if (o.z_top_m) {
    if (!(*o.z_top_m > g.z_bottom_m)) {
      throw UsageError(fmt::format("top height {} m is not above the bottom {} m", *o.z_top_m, g.z_bottom_m));
    }
    g.nz = checkedLevels(ts, g, std::ceil((*o.z_top_m - g.z_bottom_m) / o.dz_m), "the top height");
    return g;
  }
  const std::optional<double> top = condensateTopHeight_m(ts, beta, o.crop_threshold_per_m);
  // layers whose centre lies below the top, plus one empty guard layer
  const double below = top ? std::ceil((*top - g.z_bottom_m) / o.dz_m - 0.5) : 0.0;
  g.nz = checkedLevels(ts, g, std::max(below, 0.0) + 1.0, "the highest condensate");
  return g;
}

void resampleVertically(const io::ModelTimestep& ts, const ModelLevelExtinction& beta, const VerticalGrid& grid,
                        ExtinctionVolumes& out) {
  requireHeights(ts);
  out.nx = ts.nx;
  out.ny = ts.ny;
  out.nz = grid.nz;
  out.dz_m = grid.dz_m;
  out.z_bottom_m = grid.z_bottom_m;
  out.ice_per_m.assign(out.voxelCount(), 0.0f);
  out.water_per_m.assign(out.voxelCount(), 0.0f);
  const std::size_t n = std::size_t(ts.nz);

  tbb::parallel_for(tbb::blocked_range<int>(0, ts.ny), [&](const tbb::blocked_range<int>& rows) {
    std::vector<double> h(n), ice(n), water(n), d_ice(n), d_water(n);
    for (int j = rows.begin(); j != rows.end(); ++j) {
      for (int i = 0; i < ts.nx; ++i) {
        bool any = false;
        for (std::size_t k = 0; k < n; ++k) {
          const std::size_t m = ts.index(i, j, int(k));
          h[k] = double(ts.height_m[m]);
          ice[k] = double(beta.ice_per_m[m]);
          water[k] = double(beta.water_per_m[m]);
          any = any || ice[k] > 0.0 || water[k] > 0.0;
          if (!std::isfinite(h[k]) || (k > 0 && !(h[k] > h[k - 1]))) {
            throw InputError(fmt::format("{}: timestep {}: heights of column (i={}, j={}) do not increase at level {} "
                                         "({} m after {} m)",
                                         ts.source_file, ts.time_index, i, j, k, h[k], k > 0 ? h[k - 1] : 0.0));
          }
        }
        if (!any) continue;  // clear column: stays 0
        pchipSlopes(h, ice, d_ice);
        pchipSlopes(h, water, d_water);
        const double surface = surfaceHeight(ts, i, j);
        const double top = columnTop(h);
        std::size_t k = 0;  // interval [h_k, h_{k+1}] containing z (z increases with m)
        for (int layer = 0; layer < grid.nz; ++layer) {
          const double z = grid.z_bottom_m + (double(layer) + 0.5) * grid.dz_m;
          if (z < surface) continue;  // below terrain: 0
          if (z > top) break;         // above the model top: 0
          double a, b;
          if (z <= h[0]) {
            a = ice[0];
            b = water[0];
          } else if (z >= h[n - 1]) {
            a = ice[n - 1];
            b = water[n - 1];
          } else {
            while (k + 2 < n && z >= h[k + 1]) ++k;
            a = pchipEvaluate(h, ice, d_ice, k, z);
            b = pchipEvaluate(h, water, d_water, k, z);
          }
          const std::size_t q = out.index(i, j, layer);
          // PCHIP keeps values within the data range; max() only removes rounding below 0.
          out.ice_per_m[q] = static_cast<float>(std::max(a, 0.0));
          out.water_per_m[q] = static_cast<float>(std::max(b, 0.0));
        }
      }
    }
  });
}

std::vector<float> resampleFieldVertically(const io::ModelTimestep& ts, const std::vector<float>& field,
                                           const char* name, const VerticalGrid& grid) {
  if (field.empty()) return {};
  requireHeights(ts);
  if (field.size() != ts.voxelCount()) {
    throw InputError(fmt::format("{}: timestep {}: {} has {} values, expected nx*ny*nz = {}", ts.source_file,
                                 ts.time_index, name, field.size(), ts.voxelCount()));
  }
  // Zeros on huge pages (core/large_buffer.h): one output field is tens of MB.
  std::vector<float> out = hugePageFloats(std::size_t(ts.nx) * std::size_t(ts.ny) * std::size_t(grid.nz));
  const int n = ts.nz;
  tbb::parallel_for(tbb::blocked_range<int>(0, ts.ny), [&](const tbb::blocked_range<int>& rows) {
    for (int j = rows.begin(); j != rows.end(); ++j) {
      for (int i = 0; i < ts.nx; ++i) {
        int k = 0;  // interval [h_k, h_{k+1}] containing z
        for (int layer = 0; layer < grid.nz; ++layer) {
          const double z = grid.z_bottom_m + (double(layer) + 0.5) * grid.dz_m;
          while (k + 2 < n && z >= double(ts.height_m[ts.index(i, j, k + 1)])) ++k;
          double v;
          const double h0 = double(ts.height_m[ts.index(i, j, k)]);
          if (n < 2 || z <= h0) {
            v = double(field[ts.index(i, j, k)]);
          } else {
            const double h1 = double(ts.height_m[ts.index(i, j, k + 1)]);
            const double t = std::clamp((z - h0) / (h1 - h0), 0.0, 1.0);
            v = (1.0 - t) * double(field[ts.index(i, j, k)]) + t * double(field[ts.index(i, j, k + 1)]);
          }
          out[(std::size_t(layer) * std::size_t(ts.ny) + std::size_t(j)) * std::size_t(ts.nx) + std::size_t(i)] =
              static_cast<float>(v);
        }
      }
    }
  });
  return out;
}

}  // namespace nph::physics
