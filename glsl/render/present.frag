#version 450 core
// Viewer: the ray caster's linear frame to the window — exposure, tone curve and sRGB encoding, the
// same as scene/output_image.cpp writes to PNG (applyToneCurve, linearToSrgb), so a screenshot
// matches `nephele render` to 8-bit rounding. The frame's row 0 is the image's top row; the
// window's is the bottom one, hence the flipped v.
layout(binding = 0) uniform sampler2D u_frame;  // linear RGB, alpha 1
uniform float u_exposure_scale;                 // 2^exposure_ev
uniform int u_tone_curve;                       // 0 clamp, 1 Reinhard, 2 ACES fitted
in vec2 v_uv;
out vec4 o_colour;

float toneCurve(float c) {
  c = max(c, 0.0);
  if (u_tone_curve == 1) return c / (1.0 + c);  // Reinhard et al. 2002, eq. 3
  if (u_tone_curve == 2) {                      // Narkowicz 2016, input scaled by 0.6
    float x = 0.6 * c;
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
  }
  return min(c, 1.0);
}

float linearToSrgb(float l) { return l <= 0.0031308 ? 12.92 * l : 1.055 * pow(l, 1.0 / 2.4) - 0.055; }

void main() {
  vec3 c = texture(u_frame, vec2(v_uv.x, 1.0 - v_uv.y)).rgb * u_exposure_scale;
  o_colour = vec4(linearToSrgb(toneCurve(c.r)), linearToSrgb(toneCurve(c.g)), linearToSrgb(toneCurve(c.b)), 1.0);
}
