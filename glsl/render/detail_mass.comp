#version 450
// The sub-grid detail's mass measurement (issue 13 "mass preserving"; volume/detail.h): per
// half-column (2×2 per model column), the optical mass of the plain and of the uncorrected detailed
// field along u_rays_per_axis² vertical rays, midpoint rule on the lattice −H + (k + ½)·u_step_layers
// (grid units, H = u_reach_voxels) over the footprint's step range [x, y) from u_mass_range
// (volume::massStepRanges: only the layers where a sample can be non-zero, none for a footprint
// without plain mass; docs/detail.md "A cheaper mass measurement"). The CPU solves the per-column
// correction from them (solveDetailCorrection); the CPU twin is
// ExtinctionSampler::measureHalfColumnMasses. Run at upload, with u_detail_correction bound to a
// 1-texel texture of 1.
layout(local_size_x = 8, local_size_y = 8) in;
#include "dlm/volume.glsl"
layout(binding = IMAGE_DETAIL_MASS, rg32f) uniform writeonly image2D u_mass;
layout(binding = IMAGE_DETAIL_MASS_RANGE, rg32i) uniform readonly iimage2D u_mass_range;  // per model column
uniform int u_rays_per_axis;
uniform float u_step_layers;

void main() {
  ivec2 h = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(h, 2 * u_voxels.xy))) return;
  ivec2 range = imageLoad(u_mass_range, h / 2).xy;
  vec3 voxel = u_box_size_m / vec3(u_voxels);
  float g0 = -u_reach_voxels;
  float plain = 0.0, detailed = 0.0;
  for (int b = 0; b < u_rays_per_axis; ++b) {
    for (int a = 0; a < u_rays_per_axis; ++a) {
      vec2 g = 0.5 * (vec2(h) + (vec2(a, b) + 0.5) / float(u_rays_per_axis));
      float columnPlain = 0.0, columnDetailed = 0.0;
      for (int k = range.x; k < range.y; ++k) {
        vec3 w = u_box_min_m + vec3(g, g0 + (float(k) + 0.5) * u_step_layers) * voxel;
        vec2 p = plainExtinctionAt(w), d = extinctionAt(w);
        columnPlain += p.x + p.y;
        columnDetailed += d.x + d.y;
      }
      plain += columnPlain;
      detailed += columnDetailed;
    }
  }
  imageStore(u_mass, h, vec4(plain, detailed, 0.0, 0.0));
}
