#pragma once
// The extinction field as the path tracer sees it, in world space (scene/volume_frame.h), with the
// sampling rule the GPU renderer uses: trilinear between voxel centres, clamped to the border
// voxels, zero outside the volume box. β_ice and β_water in 1/m; single-scattering albedo 1, so
// they are also the scattering coefficients (Nes 2008 §5.2.2).
//
// Exact optical depth: between two neighbouring planes of voxel centres (the cells of the dual
// grid, plus the clamped half-voxel rims at the box faces) the field is a trilinear polynomial,
// so along a straight line it is a polynomial of degree ≤ 3 in the distance. Splitting a ray at
// every crossing of a voxel-centre plane and integrating each piece with 2-point Gauss–Legendre
// (exact for cubics) gives τ = ∫ β ds to rounding error — no step size, no noise. The path
// tracer's alpha channel is 1 − exp(−τ) computed this way.
#include <glm/glm.hpp>

#include "cache/extinction_volumes.h"
#include "scene/volume_frame.h"

namespace nph::reference {

struct Extinction {
  double ice_per_m = 0.0;
  double water_per_m = 0.0;
  double total_per_m() const { return ice_per_m + water_per_m; }
};

class ExtinctionField {
 public:
  /// Keeps a reference to `volumes` (which must outlive the field).
  ExtinctionField(const ExtinctionVolumes& volumes, const scene::VolumeFrame& frame);

  Extinction at(const glm::dvec3& world_m) const;
  /// The parameter range [t0, t1] (t0 ≥ t_min) where origin + t·dir lies in the volume box;
  /// false when the ray misses it. `dir` need not be unit length (t is then in units of |dir|).
  bool clipToBox(const glm::dvec3& origin_m, const glm::dvec3& dir, double t_min, double t_max, double& t0,
                 double& t1) const;
  /// Exact ∫ β_total ds along origin + t·dir (unit dir, metres) for t in [t_min, t_max].
  double opticalDepth(const glm::dvec3& origin_m, const glm::dvec3& dir, double t_min, double t_max) const;

  const scene::VolumeFrame& frame() const { return frame_; }
  const ExtinctionVolumes& volumes() const { return v_; }

 private:
  double fetchTotal(int i, int j, int k) const;
  const ExtinctionVolumes& v_;
  scene::VolumeFrame frame_;
};

}  // namespace nph::reference
