#pragma once
// The extinction field as the path tracer sees it, in world space (volume/volume_frame.h), with the
// sampling rule the GPU renderer uses — volume/extinction_sampler.h, the one CPU copy of it, for
// either reconstruction (volume/reconstruction.h) — with zero outside the grid (GL_CLAMP_TO_BORDER,
// zero border), so β fades to 0 outside each face of the volume box: over ½ voxel (trilinear) or
// 1½ voxels (cubic B-spline). The field's support is therefore the box grown by
// supportVoxels(reconstruction) on every side (`supportMin/Max`); the trackers and the exact optical
// depth work on that grown box. β_ice and β_water in 1/m; single-scattering albedo 1, so they are
// also the scattering coefficients (Nes 2008 §5.2.2).
//
// Exact optical depth: both filters are piecewise polynomials on the cells of the dual grid, between
// neighbouring planes of voxel centres g_a = i + ½ (including the rims outside the box, where the
// zero border takes part): trilinear of degree ≤ 1 per axis, the cubic B-spline (whose knots are
// the voxel centres) of degree ≤ 3 per axis. Along a straight line a piece is therefore a
// polynomial of degree ≤ 3 (trilinear) or ≤ 9 (cubic) in the distance. Splitting a ray at every
// crossing of a voxel-centre plane and integrating each piece with Gauss–Legendre — 2 nodes (exact
// to degree 3) or 5 nodes (exact to degree 9) — gives τ = ∫ β ds to rounding error: no step size,
// no noise. The path tracer's alpha channel is 1 − exp(−τ) computed this way.
#include <glm/glm.hpp>

#include "volume/extinction_sampler.h"
#include "volume/extinction_volumes.h"
#include "volume/volume_frame.h"

namespace nph::reference {

using Extinction = volume::ExtinctionSample;

class ExtinctionField {
 public:
  /// Keeps a reference to `volumes` (which must outlive the field).
  ExtinctionField(const ExtinctionVolumes& volumes, const volume::VolumeFrame& frame,
                  volume::Reconstruction reconstruction = volume::Reconstruction::Trilinear);

  Extinction at(const glm::dvec3& world_m) const { return sampler_.at(world_m); }
  volume::Reconstruction reconstruction() const { return sampler_.reconstruction(); }
  /// The support of β: the volume box grown by supportVoxels(reconstruction) on every side [world m].
  glm::dvec3 supportMin() const {
    return frame_.min_m() - volume::supportVoxels(reconstruction()) * frame_.voxel_size_m;
  }
  glm::dvec3 supportMax() const {
    return frame_.max_m() + volume::supportVoxels(reconstruction()) * frame_.voxel_size_m;
  }
  /// The parameter range [t0, t1] (t0 ≥ t_min) where origin + t·dir lies in the support box;
  /// false when the ray misses it. `dir` need not be unit length (t is then in units of |dir|).
  bool clipToBox(const glm::dvec3& origin_m, const glm::dvec3& dir, double t_min, double t_max, double& t0,
                 double& t1) const;
  /// Exact ∫ β_total ds along origin + t·dir (unit dir, metres) for t in [t_min, t_max], times
  /// VolumeFrame::opticalDepthScale(dir): the data's optical depth whatever the exaggeration.
  double opticalDepth(const glm::dvec3& origin_m, const glm::dvec3& dir, double t_min, double t_max) const;

  const volume::VolumeFrame& frame() const { return frame_; }
  /// The voxels the filter reads (for CubicInterpolating the spline coefficients): the majorants'
  /// source.
  const ExtinctionVolumes& volumes() const { return sampler_.voxels(); }

 private:
  volume::VolumeFrame frame_;
  volume::ExtinctionSampler sampler_;
};

}  // namespace nph::reference
