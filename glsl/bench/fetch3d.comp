#version 450 core
// Benchmark kernel: 3-D texture fetch throughput, the "physical limit" of a ray caster that does
// nothing but sample. Each invocation marches STEPS samples through the volume from one face,
// along u_direction (normalised texture-space step), and writes the sum so nothing is optimised
// away. Filtering (nearest/linear) and format are set on the texture by the host.
#include "common/grid.glsl"
#ifndef STEPS
#define STEPS 128
#endif
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = UNIT_BENCH_VOLUME) uniform sampler3D u_volume;
layout(r32f, binding = IMAGE_BENCH_SUM) uniform writeonly image2D u_sum;
uniform ivec2 u_rays;
uniform vec3 u_step_uvw;
void main() {
  ivec2 ray = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(ray, u_rays))) return;
  vec3 p = vec3((vec2(ray) + 0.5) / vec2(u_rays), 0.5 / float(STEPS));
  float sum = 0.0;
  for (int i = 0; i < STEPS; ++i) {
    sum += texture(u_volume, p).r;
    p = fract(p + u_step_uvw);
  }
  imageStore(u_sum, ray, vec4(sum));
}
