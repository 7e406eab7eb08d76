// glsl/common/terrain.glsl compiled as C++ in double precision (core/glsl_cpp.h), and the bounds
// the march needs, computed from the data.
#include "volume/terrain_field.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.h"
#include "core/glsl_cpp.h"

namespace nph::volume {

namespace f64 {
using namespace nph::glsl;
using glm::floor;
using std::abs;
using Number = double;
using Vec2 = glm::dvec2;
using Vec3 = glm::dvec3;
using Vec4 = glm::dvec4;
using ivec2 = glm::ivec2;
/// The shader's view of the field (the GLSL side builds the same struct from TerrainBlock).
struct TerrainGrid {
  ivec2 size;
  Vec2 cell_m;
  Number exaggeration, fade_m, max_m, min_m, lipschitz;
  const float* texels;
  bool has_far;
  ivec2 far_size;
  Vec2 far_min_m, far_cell_m;
  const float* far_texels;
};
#define TERRAIN_TEXEL(g, i, j) Number((g).texels[std::size_t(j) * std::size_t((g).size.x) + std::size_t(i)])
#define TERRAIN_FAR_TEXEL(g, i, j) Number((g).far_texels[std::size_t(j) * std::size_t((g).far_size.x) + std::size_t(i)])
#include "../glsl/common/cubic_bspline.glsl"  // the surface's weights (terrain.glsl terrainLatticeSpline)
#include "../glsl/common/terrain.glsl"
#undef TERRAIN_TEXEL
#undef TERRAIN_FAR_TEXEL

TerrainGrid gridOf(const TerrainField& t) {
  return {t.size,      t.cell_m,     t.exaggeration,       t.fade_m,   t.max_m,
          t.min_m,     t.lipschitz,  t.spline_m.data(),    t.hasFar(), t.far_size,
          t.far_min_m, t.far_cell_m, t.far_height_m.data()};
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

namespace {

/// Extremes and the largest height steps between x and y neighbours of a w × h field (x fastest).
struct FieldBounds {
  double lo = 0.0, hi = 0.0, step_x = 0.0, step_y = 0.0;
};

FieldBounds boundsOf(const std::vector<float>& h_m, int w, int h, const std::string& file, const char* what) {
  FieldBounds b;
  const auto at = [&](int i, int j) { return double(h_m[std::size_t(j) * std::size_t(w) + std::size_t(i)]); };
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const double z = at(i, j);
      if (!std::isfinite(z)) {
        throw InputError(
            fmt::format("{}: {} height at column ({}, {}) is {}; expected a finite height [m]", file, what, i, j, z));
      }
      b.lo = std::min(b.lo, z);
      b.hi = std::max(b.hi, z);
      if (i + 1 < w) b.step_x = std::max(b.step_x, std::abs(at(i + 1, j) - z));
      if (j + 1 < h) b.step_y = std::max(b.step_y, std::abs(at(i, j + 1) - z));
    }
  }
  return b;
}

/// Per line of n samples s (stride apart in `a`), in place: the coefficients c of the cubic
/// B-spline through them, (c[i−1] + 4·c[i] + c[i+1]) / 6 = s[i], with the lattice's clamp to edge
/// (c[−1] = c[0], c[n] = c[n − 1]: the indices terrain.glsl clamps), so the first and last rows
/// read (5·c[0] + c[1]) / 6 = s[0]. Thomas algorithm in double; the matrix is strictly diagonally
/// dominant (Unser 1999 prefilters the same system recursively; volume/spline_coefficients.h solves
/// it with the clouds' zero border instead).
void splineLine(std::vector<double>& a, std::size_t first, std::size_t stride, int n, std::vector<double>& cp) {
  if (n == 1) return;  // c[−1] = c[0] = c[1]: c = s
  const auto at = [&](int i) -> double& { return a[first + std::size_t(i) * stride]; };
  constexpr double kOff = 1.0 / 6.0;
  const auto diag = [&](int i) { return i == 0 || i == n - 1 ? 5.0 / 6.0 : 4.0 / 6.0; };
  cp.resize(std::size_t(n));
  cp[0] = kOff / diag(0);
  at(0) /= diag(0);
  for (int i = 1; i < n; ++i) {
    const double m = diag(i) - kOff * cp[std::size_t(i - 1)];
    cp[std::size_t(i)] = kOff / m;
    at(i) = (at(i) - kOff * at(i - 1)) / m;
  }
  for (int i = n - 2; i >= 0; --i) at(i) -= cp[std::size_t(i)] * at(i + 1);
}

/// The interpolating bicubic B-spline's coefficients of a w × h field (x fastest): along x, then y.
std::vector<float> splineCoefficients(const std::vector<float>& h_m, int w, int h) {
  std::vector<double> a(h_m.begin(), h_m.end()), cp;
  for (int j = 0; j < h; ++j) splineLine(a, std::size_t(j) * std::size_t(w), 1, w, cp);
  for (int i = 0; i < w; ++i) splineLine(a, std::size_t(i), std::size_t(w), h, cp);
  return std::vector<float>(a.begin(), a.end());
}

}  // namespace

TerrainField terrainOf(const ExtinctionVolumes& v, const VolumeFrame& frame, const DemHeights* dem) {
  TerrainField t;
  t.size = {v.nx, v.ny};
  t.cell_m = {frame.voxel_size_m.x, frame.voxel_size_m.y};
  t.exaggeration = frame.height_exaggeration;
  t.fade_m = 0.1 * std::max(frame.size_m().x, frame.size_m().y);
  const bool hasDem = dem && (!dem->model_m.empty() || !dem->far_m.empty());
  if (v.terrain_height_m.empty() && !hasDem) return t;
  const std::size_t columns = std::size_t(v.nx) * std::size_t(v.ny);
  if (!v.terrain_height_m.empty() && v.terrain_height_m.size() != columns) {
    throw InputError(fmt::format("{}: terrain has {} heights, expected {} ({}x{} columns)", v.source_file,
                                 v.terrain_height_m.size(), columns, v.nx, v.ny));
  }
  const int r = hasDem && !dem->model_m.empty() ? dem->refine : 1;
  if (r < 1 || r > kMaxTerrainRefine) {
    throw UsageError(
        fmt::format("{}: DEM lattice refined {} times, expected 1 to {}", dem->source, r, kMaxTerrainRefine));
  }
  t.size = {r * v.nx, r * v.ny};
  t.cell_m /= double(r);
  const std::vector<float> model = v.terrain_height_m.empty() ? std::vector<float>(columns, 0.0f) : v.terrain_height_m;
  if (r == 1) {
    t.height_m = model;
  } else {
    // The model's field on the refined lattice: bilinear between its mass points, clamped to its
    // edge, so that where the DEM has no data the surface is the one the model's lattice gives.
    t.height_m.resize(std::size_t(t.size.x) * std::size_t(t.size.y));
    const auto at = [&](int i, int j) { return double(model[std::size_t(j) * std::size_t(v.nx) + std::size_t(i)]); };
    for (int j = 0; j < t.size.y; ++j) {
      const double qy = std::clamp((j + 0.5) / r - 0.5, 0.0, double(v.ny - 1));
      const int j0 = int(qy), j1 = std::min(j0 + 1, v.ny - 1);
      for (int i = 0; i < t.size.x; ++i) {
        const double qx = std::clamp((i + 0.5) / r - 0.5, 0.0, double(v.nx - 1));
        const int i0 = int(qx), i1 = std::min(i0 + 1, v.nx - 1);
        const double fx = qx - i0, fy = qy - j0;
        const double h =
            (at(i0, j0) * (1.0 - fx) + at(i1, j0) * fx) * (1.0 - fy) + (at(i0, j1) * (1.0 - fx) + at(i1, j1) * fx) * fy;
        t.height_m[std::size_t(j) * std::size_t(t.size.x) + std::size_t(i)] = float(h);
      }
    }
  }
  const std::size_t texels = t.height_m.size();
  if (hasDem && !dem->model_m.empty()) {
    if (dem->model_m.size() != texels) {
      throw UsageError(fmt::format("{}: DEM resampled to {} columns, the model's lattice has {} ({}x{} x {}²)",
                                   dem->source, dem->model_m.size(), texels, v.nx, v.ny, r));
    }
    // The rule (docs/terrain.md "A user DEM"): the DEM wins where it has data, the model's own
    // field (or sea level without one) where it has none.
    for (std::size_t k = 0; k < texels; ++k) {
      if (!std::isnan(dem->model_m[k])) t.height_m[k] = dem->model_m[k];
    }
  }
  const std::string& source = hasDem ? dem->source : v.source_file;
  boundsOf(t.height_m, t.size.x, t.size.y, source, "terrain");  // finite heights, or the error naming the column
  // The surface is the cubic B-spline of the coefficients (glsl/common/terrain.glsl), so its
  // bounds are theirs: with weights ≥ 0 summing to 1 it stays within their range, and its slope
  // along x is a blend (the quadratic B-spline's weights in x times the cubic's in y) of the
  // differences between x-neighbouring coefficients, so |∂z/∂x| ≤ e·sx/dx and |∂z/∂y| ≤ e·sy/dy
  // inside the footprint. Where the heights step, the coefficients ring (by ≈ 27 % of a step,
  // decaying by 2 − √3 per lattice point), and the range and steps take that in.
  t.spline_m = splineCoefficients(t.height_m, t.size.x, t.size.y);
  const FieldBounds near = boundsOf(t.spline_m, t.size.x, t.size.y, source, "terrain spline");
  const double e = t.exaggeration;
  double lo = near.lo, hi = near.hi;
  // So, as for the bilinear surface of before, with the coefficients' steps; the fade adds at most
  // e·max|h|/fade_m, and the product h·fade keeps |∇| ≤ |∇h|·fade + |h|·|∇fade|. 1 % margin for
  // float rounding of the heights.
  const double inside = std::hypot(e * near.step_x / t.cell_m.x, e * near.step_y / t.cell_m.y);
  double lipschitz = inside + e * std::max(near.hi, -near.lo) / t.fade_m;
  if (hasDem && !dem->far_m.empty()) {
    const glm::ivec2 n = dem->far_size;
    if (n.x < 2 || n.y < 2 || dem->far_m.size() != std::size_t(n.x) * std::size_t(n.y) ||
        !(dem->far_max_m.x > dem->far_min_m.x) || !(dem->far_max_m.y > dem->far_min_m.y)) {
      throw UsageError(
          fmt::format("{}: far DEM field of {} heights for {}x{} pixels", dem->source, dem->far_m.size(), n.x, n.y));
    }
    t.far_size = n;
    t.far_min_m = dem->far_min_m;
    t.far_cell_m = (dem->far_max_m - dem->far_min_m) / glm::dvec2(n);
    t.far_height_m = dem->far_m;
    for (float& z : t.far_height_m) z = std::isnan(z) ? 0.0f : z;  // no data beyond the domain: sea level
    const FieldBounds far = boundsOf(t.far_height_m, n.x, n.y, dem->source, "far DEM");
    lo = std::min(lo, far.lo);
    hi = std::max(hi, far.hi);
    // The join: the far field is the DEM, so beyond the lattice's edge the ground goes over to it
    // within two far pixels, not a tenth of the footprint. The edge's heights are held outward
    // (clamp to edge), which over a wide fade drew a rough DEM's edge as streaks across it.
    t.fade_m = std::min(t.fade_m, 2.0 * std::max(t.far_cell_m.x, t.far_cell_m.y));
    // Beyond the footprint h = mix(h_far, h_edge, fade): |∇| ≤ |∇h_far| + |∇h_edge| + |h_edge − h_far|/fade_m,
    // and within the fade |h_edge − h_far| is at most its largest value at the lattice's edge points
    // plus what either field changes between two of them and what the far field changes across the fade.
    const f64::TerrainGrid g = f64::gridOf(t);
    double edgeGap = 0.0;
    const auto gapAt = [&](int i, int j) {
      const glm::dvec2 xy((i + 0.5) * t.cell_m.x, (j + 0.5) * t.cell_m.y);
      const double h = t.height_m[std::size_t(j) * std::size_t(t.size.x) + std::size_t(i)];
      edgeGap = std::max(edgeGap, std::abs(h - f64::terrainFarHeight_m(g, xy)));
    };
    for (int i = 0; i < t.size.x; ++i) {
      gapAt(i, 0);
      gapAt(i, t.size.y - 1);
    }
    for (int j = 0; j < t.size.y; ++j) {
      gapAt(0, j);
      gapAt(t.size.x - 1, j);
    }
    const double farSlope = std::hypot(far.step_x / t.far_cell_m.x, far.step_y / t.far_cell_m.y);
    const double gap =
        edgeGap + std::max(near.step_x, near.step_y) + std::max(far.step_x, far.step_y) + farSlope * t.fade_m;
    lipschitz = inside + e * farSlope + e * gap / t.fade_m;
  }
  t.max_m = hi * e;
  t.min_m = lo * e;
  t.lipschitz = 1.01 * lipschitz;
  return t;
}

}  // namespace nph::volume
