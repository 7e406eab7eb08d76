#pragma once
// Vertical optical depth above and below every voxel centre, at the data's true height scale
// (issue 12, sky light). The eye pass lights each sample with the sky through the cloud above it
// and with the ground-reflected light through the cloud below it, attenuated by the two-stream
// diffuse transmittance of those columns (lighting/sky_light.h); this grid gives their optical
// depths:
//   τ_up(i, j, k)   = ½·β(i, j, k)·dz + Σ_{k' > k} β(i, j, k')·dz
//   τ_down(i, j, k) = ½·β(i, j, k)·dz + Σ_{k' < k} β(i, j, k')·dz
// with β = β_ice + β_water and dz the data's layer thickness (not exaggerated: height
// exaggeration keeps the data's vertical optical depth, docs/rendering.md "Conventions").
// Sampled like the extinction volumes — trilinear between voxel centres — but clamped to the edge
// (outside the grid the nearest column's depths hold; above the top τ_up → its value at the top
// centre, which is ½β·dz, small).
#include <vector>

#include <glm/glm.hpp>

#include "volume/extinction_volumes.h"
#include "volume/volume_frame.h"

namespace nph {

/// Depths rounded to half precision, the GPU texture's storage (RG16F), so that the CPU twin
/// samples exactly the values the eye pass does.
struct ColumnDepths {
  int nx = 0, ny = 0, nz = 0;
  std::vector<float> up;    ///< τ_up per voxel, ExtinctionVolumes::index layout
  std::vector<float> down;  ///< τ_down per voxel
};

/// The vertical optical depths of `volumes` (O(voxels), one pass per column).
ColumnDepths columnDepths(const ExtinctionVolumes& volumes);

/// (τ_up, τ_down) at a world point: trilinear between voxel centres, clamped to the edge (the GPU
/// rule of the RG texture UNIT_COLUMN_DEPTH: GL_LINEAR, GL_CLAMP_TO_EDGE).
glm::dvec2 columnDepthAt(const ColumnDepths& depths, const scene::VolumeFrame& frame, const glm::dvec3& world_m);

}  // namespace nph
