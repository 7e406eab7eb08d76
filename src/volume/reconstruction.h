#pragma once
// How the renderer reconstructs a continuous extinction field β(x) from the voxels: the one
// definition shared by the shaders (glsl/dlm/volume.glsl extinctionAt), the CPU sampler
// (extinction_sampler.h), the occupancy grid (occupancy.h), the path tracer's field and majorant
// grid (reference/) and the knob `reconstruction` (lighting/knobs.h).
//
// Both filters are centred on the voxel centres (grid coordinate i + ½) and see zero outside the
// grid (GL_CLAMP_TO_BORDER, zero border):
//   - Trilinear: the tensor product of the hat function, support ±1 voxel. Interpolates the voxels;
//     its derivative jumps at every voxel-centre plane, and an optically thick cell's visible
//     surface sits on the grid: on coarse model data (10 km, 30 levels) clouds show the columns and
//     the levels as terraces and blocks (issue 13).
//   - Cubic: the tensor product of the uniform cubic B-spline (Sigg & Hadwiger 2005, "Fast
//     third-order texture filtering", GPU Gems 2 ch. 20; Muth 2026 §3.3.1 uses the same weights
//     horizontally), support ±2 voxels. C² continuous, non-negative weights summing to 1 (so β
//     stays within the range of the voxels it reads, and ∫β over all space — the optical mass — is
//     unchanged), but it approximates rather than interpolates: peaks are lowered and spread.
//     The shaders evaluate it with 8 trilinear fetches per phase, the CPU with the 64 weights.
//   - CubicInterpolating: the same B-spline evaluated on the interpolating spline's coefficients
//     (volume/spline_coefficients.h), so it passes through the voxels: C² and data-true at the
//     voxel centres. Every consumer that filters β (the upload's textures, the CPU sampler, the
//     occupancy maxima) converts the voxels to the coefficients first and then evaluates the cubic
//     weights (`cubicWeights`), clamping β at 0 (the spline rings below 0 at cloud edges); the
//     column depths are the coefficients' sums (clamped at 0), the detail's controls keep the
//     voxels. Reach, support and cost are the
//     cubic B-spline's; the path tracer's optical depths (Gauss nodes per polynomial piece) are
//     exact except where the clamp cuts a piece.
//
// Reach: a point in voxel cell v (grid coordinates in [v, v + 1) per axis) reads the voxels
// v − reach … v + reach on each axis (trilinear: v − 1 … v + 1, cubic: v − 2 … v + 2). β is 0
// beyond `supportVoxels` = reach − ½ voxels outside the box. The occupancy bricks are dilated by
// the reach and the grown boxes padded by it, so empty-space skipping stays exact for both.
#include <array>
#include <cmath>
#include <string_view>

#include <glm/glm.hpp>

#include "core/glsl_cpp.h"

namespace nph::volume {

enum class Reconstruction { Trilinear = 0, Cubic = 1, CubicInterpolating = 2 };

/// Names in the order of the enum values (scene files, docs).
inline constexpr std::array<std::string_view, 3> kReconstructionNames{"trilinear", "cubic", "cubic_interpolating"};

/// Whether `r` evaluates the cubic B-spline's weights (on the voxels or on their spline coefficients).
constexpr bool cubicWeights(Reconstruction r) { return r != Reconstruction::Trilinear; }
/// Whether `r` reads the interpolating spline's coefficients instead of the voxels.
constexpr bool readsSplineCoefficients(Reconstruction r) { return r == Reconstruction::CubicInterpolating; }

/// Voxels a sample reads beyond its own cell, per side (see above).
constexpr int reachVoxels(Reconstruction r) { return cubicWeights(r) ? 2 : 1; }
/// How far β reaches outside the box [voxels]: reach − ½.
constexpr double supportVoxels(Reconstruction r) { return double(reachVoxels(r)) - 0.5; }

namespace cubic_f64 {  // glsl/common/cubic_bspline.glsl compiled as C++ in double (core/glsl_cpp.h)
using namespace nph::glsl;
using Number = double;
using Vec4 = glm::dvec4;
/// The shared file's functions as members (defined in the class: inline, so this header may be
/// included anywhere).
struct CubicBSpline {
#include "../glsl/common/cubic_bspline.glsl"
};
}  // namespace cubic_f64

/// Uniform cubic B-spline weights of the four voxels around a sample at fraction f ∈ [0, 1) past
/// voxel centre c₁: voxels c₁ − 1, c₁, c₁ + 1, c₁ + 2 (Sigg & Hadwiger 2005, eq. 20.3) — the
/// shaders' weights (glsl/common/cubic_bspline.glsl).
inline std::array<double, 4> cubicBSplineWeights(double f) {
  const glm::dvec4 w = cubic_f64::CubicBSpline{}.cubicBSplineWeights(f);
  return {w.x, w.y, w.z, w.w};
}

/// The shaders' merge of those weights into two linear fetches: (g0, g1, h0, h1) (cubic_bspline.glsl).
inline glm::dvec4 cubicBSplineFetches(double f) { return cubic_f64::CubicBSpline{}.cubicBSplineFetches(f); }

/// The filter's weighted sum of the voxels around a point at continuous index `c` relative to the
/// voxel centres (voxel centres at integers: grid coordinate − ½): Σ w·fetch(i, j, k) over the
/// 2³ (trilinear) or 4³ (cubic) voxels it reads. `fetch` applies the border rule — zero outside
/// for β (GL_CLAMP_TO_BORDER), clamped to the edge for the column depths (column_depth.h) — and
/// may return any type with + and scalar × (a double, or a glm vector for several channels read
/// together). The one CPU evaluation of both filters; the shaders' is glsl/dlm/volume.glsl.
template <class Fetch>
auto reconstructAt(Reconstruction r, const glm::dvec3& c, Fetch&& fetch) -> decltype(fetch(0, 0, 0)) {
  using Value = decltype(fetch(0, 0, 0));
  const glm::dvec3 lo = glm::floor(c);
  const glm::dvec3 f = c - lo;
  const glm::ivec3 i0(lo);
  const bool cubic = cubicWeights(r);
  const int taps = cubic ? 4 : 2, first = cubic ? -1 : 0;
  std::array<std::array<double, 4>, 3> w{};
  for (int a = 0; a < 3; ++a)
    w[std::size_t(a)] = cubic ? cubicBSplineWeights(f[a]) : std::array<double, 4>{1.0 - f[a], f[a], 0.0, 0.0};
  Value sum{};
  for (int dz = 0; dz < taps; ++dz)
    for (int dy = 0; dy < taps; ++dy) {
      const double wyz = w[1][std::size_t(dy)] * w[2][std::size_t(dz)];
      for (int dx = 0; dx < taps; ++dx) {
        const double wt = w[0][std::size_t(dx)] * wyz;
        if (wt != 0.0) sum += wt * fetch(i0.x + first + dx, i0.y + first + dy, i0.z + first + dz);
      }
    }
  return sum;
}

}  // namespace nph::volume
