#version 450
// The sub-grid detail's periodic noise tile (issue 13; glsl/common/noise.glsl), generated once per
// upload that needs it (Thomann 2021 §4.4: a compute shader fills the 3-D texture, one noise per
// channel). CPU twin: volume/noise.cpp (same file compiled as C++).
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#include "common/noise.glsl"
layout(binding = IMAGE_DETAIL_NOISE, rgba8) uniform writeonly image3D u_noise;
uniform int u_size;

void main() {
  ivec3 t = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(t, ivec3(u_size)))) return;
  imageStore(u_noise, t, noiseTexel(t, u_size));
}
