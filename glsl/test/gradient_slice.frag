#version 450 core
// GL foundation test: draws slice u_slice of the gradient into a 2-D target (raster path).
#include "test/gradient.glsl"
uniform int u_slice;
layout(location = 0) out vec4 o_colour;
void main() {
  o_colour = gradientValue(ivec3(ivec2(gl_FragCoord.xy), u_slice));
}
