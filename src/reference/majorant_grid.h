#pragma once
// Majorant grid for delta and ratio tracking (Woodcock et al. 1965; Novák et al. 2014 "Residual
// ratio tracking"; Kutz et al. 2017 §3 for piecewise-constant majorants).
//
// The volume is split into bricks of `brick_voxels`³ voxels (default 8: an 8³ brick keeps the
// majorant tight at cloud edges while a typical 200×200×60 volume has only 25×25×8 bricks to
// walk). Each brick stores μ̄ ≥ β_ice + β_water at every point of its world-space box. A point in
// brick [bB, (b+1)B) (grid units) reads voxels bB − R … (b+1)B − 1 + R on that axis, R the
// filter's reach (1 trilinear, 2 cubic B-spline; volume/reconstruction.h); both filters have
// non-negative weights summing to at most 1, so μ̄ = the maximum of β_ice + β_water over that
// range, clamped to the volume, is an exact bound, not a heuristic. The outermost bricks also
// cover the rim outside the box where β fades to the zero border (½ voxel trilinear, 1½ cubic;
// path_tracer_field.h). Bricks with μ̄ = 0 are skipped by the trackers without sampling
// (empty-space skipping).
//
// Traversal: a 3D DDA (Amanatides & Woo 1987) over the bricks along a ray yields the segments
// [t_a, t_b) with a constant μ̄; free-flight sampling restarts at each segment boundary, which is
// valid because the exponential distribution is memoryless.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "reference/path_tracer_field.h"

namespace nph::reference {

inline constexpr int kDefaultBrickVoxels = 8;

class MajorantGrid {
 public:
  /// Throws InputError when a voxel is NaN, infinite or negative (the trackers need a bound).
  /// Keeps a reference to `field`, which must outlive the grid.
  explicit MajorantGrid(const ExtinctionField& field, int brick_voxels = kDefaultBrickVoxels);

  glm::ivec3 bricks() const { return bricks_; }
  int brickVoxels() const { return brick_; }
  double majorant(int bx, int by, int bz) const {
    return majorant_[(std::size_t(bz) * std::size_t(bricks_.y) + std::size_t(by)) * std::size_t(bricks_.x) +
                     std::size_t(bx)];
  }
  /// μ̄ of the brick containing a world point (0 outside the support: the box grown by
  /// supportVoxels(reconstruction)).
  double majorantAt(const glm::dvec3& world_m) const;

  /// Calls visit(μ̄ [1/m], t_a, t_b) for consecutive segments covering [t0, t1] ∩ box along
  /// origin + t·dir (unit dir, metres), in order; stops early when visit returns false.
  template <class Visit>
  void traverse(const glm::dvec3& origin_m, const glm::dvec3& dir, double t0, double t1, Visit&& visit) const;

 private:
  const ExtinctionField& field_;
  int brick_ = kDefaultBrickVoxels;
  glm::ivec3 bricks_{0};
  std::vector<double> majorant_;
};

template <class Visit>
void MajorantGrid::traverse(const glm::dvec3& origin_m, const glm::dvec3& dir, double t0, double t1,
                            Visit&& visit) const {
  double ta = 0.0, tb = 0.0;
  if (!field_.clipToBox(origin_m, dir, t0, t1, ta, tb)) return;
  const volume::VolumeFrame& f = field_.frame();
  const glm::dvec3 g0 = f.gridFromWorld(origin_m);
  const glm::dvec3 gd = dir / f.voxel_size_m;
  const double b = double(brick_);
  // The outermost bricks reach on to the support's faces (past the box, where β fades to 0; their
  // μ̄ bounds that rim too, since it reads only zero-border voxels and the edge voxels): no
  // crossing leaves them in the outward direction.
  constexpr double kNever = std::numeric_limits<double>::infinity();
  glm::ivec3 idx{0}, step{0};
  glm::dvec3 tNext{0.0}, tDelta{0.0};
  for (int a = 0; a < 3; ++a) {
    const double p = (g0[a] + ta * gd[a]) / b;  // on a brick face: a zero-length first segment
    idx[a] = std::clamp(int(std::floor(p)), 0, bricks_[a] - 1);
    if (gd[a] > 0.0) {
      step[a] = 1;
      tNext[a] = idx[a] == bricks_[a] - 1 ? kNever : ((double(idx[a]) + 1.0) * b - g0[a]) / gd[a];
      tDelta[a] = b / gd[a];
    } else if (gd[a] < 0.0) {
      step[a] = -1;
      tNext[a] = idx[a] == 0 ? kNever : (double(idx[a]) * b - g0[a]) / gd[a];
      tDelta[a] = -b / gd[a];
    } else {
      tNext[a] = std::numeric_limits<double>::infinity();
      tDelta[a] = std::numeric_limits<double>::infinity();
    }
  }
  double t = ta;
  for (;;) {
    const int axis = tNext.x <= tNext.y ? (tNext.x <= tNext.z ? 0 : 2) : (tNext.y <= tNext.z ? 1 : 2);
    const double tExit = std::min(tNext[axis], tb);
    if (tExit > t && !visit(majorant(idx.x, idx.y, idx.z), t, tExit)) return;
    if (tExit >= tb) return;
    t = std::max(t, tExit);
    idx[axis] += step[axis];
    const bool outermost = step[axis] > 0 ? idx[axis] == bricks_[axis] - 1 : idx[axis] == 0;
    tNext[axis] = outermost ? kNever : tNext[axis] + tDelta[axis];
  }
}

}  // namespace nph::reference
