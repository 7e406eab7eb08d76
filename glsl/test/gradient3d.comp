#version 450 core
// GL foundation test: writes a gradient into a 3-D RGBA32F image.
#include "common/grid.glsl"
#include "test/gradient.glsl"
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(rgba32f, binding = IMAGE_TEST_OUT) uniform writeonly image3D u_out;
uniform ivec3 u_size;
void main() {
  ivec3 v = ivec3(gl_GlobalInvocationID);
  if (!insideGrid(v, u_size)) return;
  imageStore(u_out, v, gradientValue(v));
}
