#version 450
// The sub-grid detail's mass measurement (issue 13 "mass preserving"; volume/detail.h): per
// half-column (2×2 per model column), the optical mass of the plain and of the uncorrected detailed
// field along kMassRaysPerAxis² vertical rays, midpoint rule with kMassStepLayers layers over the
// grown box. The CPU solves the per-column correction from them (solveDetailCorrection); the CPU
// twin is ExtinctionSampler::measureHalfColumnMasses. Run at upload, with u_detail_correction
// bound to a 1-texel texture of 1.
layout(local_size_x = 8, local_size_y = 8) in;
#include "dlm/volume.glsl"
layout(binding = IMAGE_DETAIL_MASS, rg32f) uniform writeonly image2D u_mass;
uniform int u_rays_per_axis;
uniform float u_step_layers;

void main() {
  ivec2 h = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(h, 2 * u_voxels.xy))) return;
  vec3 voxel = u_box_size_m / vec3(u_voxels);
  float g0 = -u_reach_voxels, g1 = float(u_voxels.z) + u_reach_voxels;
  int steps = int(ceil((g1 - g0) / u_step_layers));
  float plain = 0.0, detailed = 0.0;
  for (int b = 0; b < u_rays_per_axis; ++b) {
    for (int a = 0; a < u_rays_per_axis; ++a) {
      vec2 g = 0.5 * (vec2(h) + (vec2(a, b) + 0.5) / float(u_rays_per_axis));
      float columnPlain = 0.0, columnDetailed = 0.0;
      for (int k = 0; k < steps; ++k) {
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
