// glsl/common/terrain.glsl compiled as C++ in double precision (core/glsl_cpp.h), and the bounds
// the march needs, computed from the data.
#include "volume/terrain_field.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.h"
#include "core/glsl_cpp.h"

namespace nph::scene {

namespace f64 {
using namespace nph::glsl;
using glm::floor;
using std::abs;
using Number = double;
using Vec2 = glm::dvec2;
using Vec3 = glm::dvec3;
using ivec2 = glm::ivec2;
/// The shader's view of the field (the GLSL side builds the same struct from TerrainBlock).
struct TerrainGrid {
  ivec2 size;
  Vec2 cell_m;
  Number exaggeration, fade_m, max_m, min_m, lipschitz;
  const float* texels;
};
#define TERRAIN_TEXEL(g, i, j) Number((g).texels[std::size_t(j) * std::size_t((g).size.x) + std::size_t(i)])
#include "../glsl/common/terrain.glsl"
#undef TERRAIN_TEXEL

TerrainGrid gridOf(const TerrainField& t) {
  return {t.size, t.cell_m, t.exaggeration, t.fade_m, t.max_m, t.min_m, t.lipschitz, t.height_m.data()};
}
}  // namespace f64

double TerrainField::heightAt(const glm::dvec2& xy_m) const {
  return present() ? f64::terrainHeight_m(f64::gridOf(*this), xy_m) : 0.0;
}

glm::dvec3 TerrainField::normalAt(const glm::dvec2& xy_m) const {
  return present() ? f64::terrainNormal(f64::gridOf(*this), xy_m) : glm::dvec3(0.0, 0.0, 1.0);
}

double TerrainField::hitDistance(const glm::dvec3& origin_m, const glm::dvec3& dir, double t_min, double t_max) const {
  double t = -1.0;
  if (present()) {
    t = f64::terrainHitDistance(f64::gridOf(*this), origin_m, dir, t_min, t_max);
  } else if (dir.z < 0.0) {
    t = -origin_m.z / dir.z;
  }
  return t >= t_min && t <= t_max && t < f64::kTerrainMiss_m ? t : -1.0;
}

TerrainField terrainOf(const ExtinctionVolumes& v, const VolumeFrame& frame) {
  TerrainField t;
  t.size = {v.nx, v.ny};
  t.cell_m = {frame.voxel_size_m.x, frame.voxel_size_m.y};
  t.exaggeration = frame.height_exaggeration;
  t.fade_m = 0.1 * std::max(frame.size_m().x, frame.size_m().y);
  if (v.terrain_height_m.empty()) return t;
  const std::size_t columns = std::size_t(v.nx) * std::size_t(v.ny);
  if (v.terrain_height_m.size() != columns) {
    throw InputError(fmt::format("{}: terrain has {} heights, expected {} ({}x{} columns)", v.source_file,
                                 v.terrain_height_m.size(), columns, v.nx, v.ny));
  }
  t.height_m = v.terrain_height_m;
  double lo = 0.0, hi = 0.0, sx = 0.0, sy = 0.0;  // extremes; largest height step between neighbours
  for (int j = 0; j < v.ny; ++j) {
    for (int i = 0; i < v.nx; ++i) {
      const double h = t.height_m[std::size_t(j) * std::size_t(v.nx) + std::size_t(i)];
      if (!std::isfinite(h)) {
        throw InputError(fmt::format("{}: terrain height at column ({}, {}) is {}; expected a finite height [m]",
                                     v.source_file, i, j, h));
      }
      lo = std::min(lo, h);
      hi = std::max(hi, h);
      if (i + 1 < v.nx)
        sx = std::max(sx, std::abs(double(t.height_m[std::size_t(j) * std::size_t(v.nx) + std::size_t(i + 1)]) - h));
      if (j + 1 < v.ny)
        sy = std::max(sy, std::abs(double(t.height_m[std::size_t(j + 1) * std::size_t(v.nx) + std::size_t(i)]) - h));
    }
  }
  const double e = t.exaggeration;
  t.max_m = hi * e;
  t.min_m = lo * e;
  // A bilinear patch's gradient is a blend of its edges' differences, so |∂z/∂x| ≤ e·sx/dx and
  // |∂z/∂y| ≤ e·sy/dy inside the footprint; the fade adds at most e·max|h|/fade_m, and the product
  // h·fade keeps |∇| ≤ |∇h|·fade + |h|·|∇fade|. 1 % margin for float rounding of the heights.
  const double inside = std::hypot(e * sx / t.cell_m.x, e * sy / t.cell_m.y);
  t.lipschitz = 1.01 * (inside + e * std::max(hi, -lo) / t.fade_m);
  return t;
}

}  // namespace nph::scene
