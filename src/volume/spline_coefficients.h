#pragma once
// The interpolating cubic spline of the extinction (issue 13; docs/rendering.md "A grid-free
// storm"): the reconstruction `cubic_interpolating` (volume/reconstruction.h) evaluates the same
// tricubic B-spline as `cubic` — the shaders' 8 trilinear fetches, the CPU's 64 weights — but on
// coefficients c instead of the voxels s, chosen so that the spline passes through the voxels
// (Unser, "Splines: a perfect fit for signal and image processing", IEEE SPM 1999; Thévenaz, Blu &
// Unser, "Interpolation revisited", IEEE TMI 2000 §IV: "prefiltering"). The plain B-spline of the
// voxels lowers and spreads every peak (its transfer function is sinc⁴); the interpolating one keeps
// the data's values at the voxel centres and is still C² — on the grid-free storm it is 17× closer
// to the fine-grid truth than the B-spline below ½ cycle per column and 7× closer than trilinear
// at the column spacing (tests/render/reconstruction_gl_test.cpp).
//
// Per axis, with the GPU's zero border (the coefficients outside the grid are 0, as
// GL_CLAMP_TO_BORDER reads them), the voxel centres give the tridiagonal system
//   (c[i−1] + 4·c[i] + c[i+1]) / 6 = s[i],  i = 0 … n − 1,  c[−1] = c[n] = 0,
// solved exactly in double (Thomas algorithm; the matrix is strictly diagonally dominant), along x,
// then y, then z. Where the field drops to clear air the spline rings: coefficients there go
// negative and are kept (clamping them at 0 instead spreads every cloud by up to two voxels — on
// the coarse storm the towers swelled visibly); the filtered β is clamped at 0 instead (glsl/dlm/
// volume.glsl plainExtinctionAt, ExtinctionSampler::plainAt). With weights ≥ 0 summing to 1, β
// still never exceeds the largest coefficient it reads, so the occupancy bricks' maxima — taken
// over the coefficients — stay bounds.
#include <vector>

#include "volume/extinction_volumes.h"

namespace nph::volume {

/// In place: `a` (nx × ny × nz, x fastest) replaced by its interpolating spline coefficients.
void interpolatingSplineCoefficients(std::vector<float>& a, int nx, int ny, int nz);

/// `volumes` with the ice and water extinctions replaced by their interpolating spline coefficients
/// (maxima recomputed; terrain and the detail's fields unchanged).
ExtinctionVolumes splineCoefficientVolumes(const ExtinctionVolumes& volumes);

}  // namespace nph::volume
