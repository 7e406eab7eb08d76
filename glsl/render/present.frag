#version 450 core
// Viewer: the ray caster's linear frame to the window — exposure, tone curve and sRGB encoding of
// glsl/common/display.glsl, the source scene/output_image.cpp compiles as C++ for the PNG, so a
// screenshot matches `nephele render` to 8-bit rounding. The frame's row 0 is the image's top
// row; the window's is the bottom one, hence the flipped v.
#include "common/display.glsl"
layout(binding = UNIT_PRESENT_FRAME) uniform sampler2D u_frame;  // linear RGB, alpha 1
uniform vec3 u_exposure_scale;  // 2^exposure_ev × the white balance's gain (scene::radianceScale)
uniform int u_tone_curve;                       // kToneCurve* (scene::ToneCurve)
in vec2 v_uv;
out vec4 o_colour;

void main() {
  vec3 c = texture(u_frame, vec2(v_uv.x, 1.0 - v_uv.y)).rgb * u_exposure_scale;
  o_colour = vec4(linearToSrgb(toneCurve(c.r, u_tone_curve)), linearToSrgb(toneCurve(c.g, u_tone_curve)),
                  linearToSrgb(toneCurve(c.b, u_tone_curve)), 1.0);
}
