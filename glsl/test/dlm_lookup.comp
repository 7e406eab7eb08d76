#version 450 core
// DLM look-up test: evaluates dlmIntensity at world points from a buffer (glsl/dlm/lookup.glsl).
#include "dlm/light_space.glsl"
#include "dlm/lookup.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = SSBO_TEST_POINTS) readonly buffer Points { vec4 points[]; };
layout(std430, binding = SSBO_TEST_RESULTS) writeonly buffer Results { float results[]; };
uniform int u_count;
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= u_count) return;
  results[i] = dlmIntensity(points[i].xyz);
}
