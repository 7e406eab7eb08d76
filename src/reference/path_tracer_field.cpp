#include "reference/path_tracer_field.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "core/error.h"

namespace nph::reference {

ExtinctionField::ExtinctionField(const ExtinctionVolumes& volumes, const volume::VolumeFrame& frame,
                                 volume::Reconstruction reconstruction)
    : frame_(frame), sampler_(volumes, frame, reconstruction) {
  const std::size_t n = volumes.voxelCount();
  if (n == 0 || frame.voxels != glm::ivec3(volumes.nx, volumes.ny, volumes.nz)) {
    throw UsageError("ExtinctionField: frame does not match the volume (" + std::to_string(volumes.nx) + "x" +
                     std::to_string(volumes.ny) + "x" + std::to_string(volumes.nz) + ")");
  }
  if ((!volumes.ice_per_m.empty() && volumes.ice_per_m.size() != n) ||
      (!volumes.water_per_m.empty() && volumes.water_per_m.size() != n)) {
    throw UsageError("ExtinctionField: ice/water arrays must be empty or hold nx*ny*nz values");
  }
}

bool ExtinctionField::clipToBox(const glm::dvec3& origin_m, const glm::dvec3& dir, double t_min, double t_max,
                                double& t0, double& t1) const {
  const glm::dvec3 lo = supportMin(), hi = supportMax();
  t0 = t_min;
  t1 = t_max;
  for (int a = 0; a < 3; ++a) {
    if (dir[a] == 0.0) {
      if (origin_m[a] < lo[a] || origin_m[a] > hi[a]) return false;
      continue;
    }
    const double inv = 1.0 / dir[a];
    double ta = (lo[a] - origin_m[a]) * inv, tb = (hi[a] - origin_m[a]) * inv;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 < t1;
}

double ExtinctionField::opticalDepth(const glm::dvec3& origin_m, const glm::dvec3& dir, double t_min,
                                     double t_max) const {
  double t0 = 0.0, t1 = 0.0;
  if (!clipToBox(origin_m, dir, t_min, t_max, t0, t1)) return 0.0;
  // Break points: crossings of the voxel-centre planes g_a = i + ½, i = −R … n_a − 1 + R with R the
  // reach (1 trilinear, 2 cubic: the outer two bound the support), visited in order by a three-way
  // merge of the per-axis arithmetic sequences (a DDA over the dual grid).
  const int reach = volume::reachVoxels(reconstruction());
  const glm::dvec3 g0 = frame_.gridFromWorld(origin_m);
  const glm::dvec3 gd = dir / frame_.voxel_size_m;
  glm::ivec3 plane{0}, step{0};
  glm::dvec3 tCross{std::numeric_limits<double>::infinity()};
  for (int a = 0; a < 3; ++a) {
    if (gd[a] == 0.0) continue;
    const double ga = g0[a] + t0 * gd[a];
    step[a] = gd[a] > 0.0 ? 1 : -1;
    plane[a] = gd[a] > 0.0 ? int(std::ceil(ga - 0.5)) : int(std::floor(ga - 0.5));
    plane[a] = std::clamp(plane[a], -reach - 1, frame_.voxels[a] + reach);
    if (plane[a] >= -reach && plane[a] <= frame_.voxels[a] - 1 + reach) {
      tCross[a] = (double(plane[a]) + 0.5 - g0[a]) / gd[a];
    }
  }
  // Gauss–Legendre on [−½, ½] (nodes and weights of the unit interval): 2 nodes (±1/(2√3), ½ each)
  // are exact to degree 3 (trilinear pieces), 5 nodes to degree 9 (tricubic pieces).
  struct Node {
    double x, w;
  };
  static const std::array<Node, 2> kGauss2{{{-0.5 / std::sqrt(3.0), 0.5}, {0.5 / std::sqrt(3.0), 0.5}}};
  static const std::array<Node, 5> kGauss5 = [] {
    const double a = std::sqrt(5.0 - 2.0 * std::sqrt(10.0 / 7.0)) / 3.0;  // Abramowitz & Stegun 25.4.30
    const double b = std::sqrt(5.0 + 2.0 * std::sqrt(10.0 / 7.0)) / 3.0;
    const double wa = (322.0 + 13.0 * std::sqrt(70.0)) / 900.0, wb = (322.0 - 13.0 * std::sqrt(70.0)) / 900.0;
    return std::array<Node, 5>{{{-0.5 * b, 0.5 * wb},
                                {-0.5 * a, 0.5 * wa},
                                {0.0, 0.5 * 128.0 / 225.0},
                                {0.5 * a, 0.5 * wa},
                                {0.5 * b, 0.5 * wb}}};
  }();
  const std::span<const Node> nodes =
      volume::cubicWeights(reconstruction()) ? std::span<const Node>(kGauss5) : std::span<const Node>(kGauss2);
  double tau = 0.0;
  for (double t = t0;;) {
    int axis = -1;
    double tNext = t1;
    for (int a = 0; a < 3; ++a) {
      if (tCross[a] < tNext) {
        tNext = tCross[a];
        axis = a;
      }
    }
    if (tNext > t) {
      const double mid = 0.5 * (t + tNext), len = tNext - t;
      double piece = 0.0;
      for (const Node& q : nodes) piece += q.w * at(origin_m + (mid + q.x * len) * dir).total();
      tau += len * piece;
      t = tNext;
    }
    if (axis < 0) break;
    plane[axis] += step[axis];
    tCross[axis] = (plane[axis] >= -reach && plane[axis] <= frame_.voxels[axis] - 1 + reach)
                       ? (double(plane[axis]) + 0.5 - g0[axis]) / gd[axis]
                       : std::numeric_limits<double>::infinity();
  }
  return tau * frame_.opticalDepthScale(dir);  // the data's τ whatever the height exaggeration
}

}  // namespace nph::reference
