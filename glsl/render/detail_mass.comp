#version 450
// The sub-grid detail's mass measurement (issue 13 "mass preserving"; volume/detail.h): per
// vertical ray ((2·u_rays_per_axis)² per model column, at the centres of a regular sub-grid of its
// footprint), the optical mass of the plain and of the uncorrected detailed field, midpoint rule on
// the lattice −H + (k + ½)·u_step_layers (grid units, H = u_reach_voxels) over the footprint's step
// range [x, y) from u_mass_range (volume::massStepRanges: only the layers where a sample can be
// non-zero, none for a footprint without plain mass; docs/detail.md "A cheaper mass measurement").
// Per ray, not summed per footprint: the correction blends between columns near their faces, so
// the CPU solves it with each ray's own weights (solveDetailCorrection). The CPU twin is
// ExtinctionSampler::measureRayMasses. Run at upload, with u_columns' correction bound to a
// 1-texel texture of 1.
layout(local_size_x = 8, local_size_y = 8) in;
#include "dlm/volume.glsl"
layout(binding = IMAGE_DETAIL_MASS, rg32f) uniform writeonly image2D u_mass;
layout(binding = IMAGE_DETAIL_MASS_RANGE, rg32i) uniform readonly iimage2D u_mass_range;  // per model column
uniform int u_rays_per_axis;  // per half-column and axis
uniform float u_step_layers;

void main() {
  ivec2 ray = ivec2(gl_GlobalInvocationID.xy);
  int perColumn = 2 * u_rays_per_axis;
  if (any(greaterThanEqual(ray, perColumn * u_voxels.xy))) return;
  ivec2 range = imageLoad(u_mass_range, ray / perColumn).xy;
  vec3 voxel = u_box_size_m / vec3(u_voxels);
  float g0 = -u_reach_voxels;
  vec2 g = (vec2(ray) + 0.5) / float(perColumn);
  float plain = 0.0, detailed = 0.0;
  for (int k = range.x; k < range.y; ++k) {
    vec3 w = u_box_min_m + vec3(g, g0 + (float(k) + 0.5) * u_step_layers) * voxel;
    vec2 p = plainExtinctionAt(w), d = extinctionAt(w);
    plain += p.x + p.y;
    detailed += d.x + d.y;
  }
  imageStore(u_mass, ray, vec4(plain, detailed, 0.0, 0.0));
}
