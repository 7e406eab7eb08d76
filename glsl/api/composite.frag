#version 450 core
// Plugin API composite pass: the premultiplied linear cloud layer (or the full frame) of the ray
// caster into the host's framebuffer, blended "over" (Porter & Duff 1984):
//   C_out = C_layer + (1 − α_layer) · C_host,   α_out = α_layer + (1 − α_layer) · α_host
// with glBlendFuncSeparate(ONE, ONE_MINUS_SRC_ALPHA, ONE, ONE_MINUS_SRC_ALPHA) set by the API.
//
// The layer's row 0 is the top of the image (clouds.comp), GL's window row 0 the bottom: rows
// are flipped here. When the viewport has the layer's size every pixel fetches its own texel
// (bit-exact); otherwise the layer is sampled bilinearly across the viewport.
//
// Output transform (u_display): 0 = linear radiance (sun radiance 1) times 2^exposure, for hosts
// that blend in linear light (enable GL_FRAMEBUFFER_SRGB on an sRGB target for display);
// 1 = display-referred like `nephele render`'s PNG (scene/output_image.h): un-premultiply,
// exposure and white balance, ACES fitted tone curve (Narkowicz 2016), sRGB encode (IEC 61966-2-1), re-premultiply —
// glsl/common/display.glsl, the very source the PNG writer compiles as C++; the frei0r test
// compares both paths code for code.
//
// Pass copies (plugin API v2 pass_to_texture; scene/passes.h): blending off, u_select picks what
// the packed pass texture holds: 0 = RGBA as is, 1 = RGB with α = 1 (ground, sky: the packed
// textures keep the shadow matte / depth in α), 2 = α broadcast to RGB with α = 1 (shadow, depth).
#include "common/display.glsl"
layout(binding = UNIT_COMPOSITE_LAYER) uniform sampler2D u_layer;
uniform vec4 u_viewport;  // x, y, width, height of the host viewport [pixels]
uniform vec3 u_exposure_scale;  // 2^exposure_ev × the white balance's gain (scene/white_balance.h)
uniform int u_display;
uniform int u_select;

in vec2 v_uv;
layout(location = 0) out vec4 o_colour;

void main() {
  ivec2 size = textureSize(u_layer, 0);
  vec4 c;
  if (ivec2(u_viewport.zw) == size) {
    ivec2 px = ivec2(gl_FragCoord.xy - u_viewport.xy);
    c = texelFetch(u_layer, ivec2(px.x, size.y - 1 - px.y), 0);
  } else {
    c = texture(u_layer, vec2(v_uv.x, 1.0 - v_uv.y));
  }
  if (u_select == 1) c.a = 1.0;
  if (u_select == 2) c = vec4(c.aaa, 1.0);
  c.rgb *= u_exposure_scale;
  if (u_display == 1) {
    float alpha = clamp(c.a, 0.0, 1.0);
    vec3 straight = alpha > 0.0 ? c.rgb / alpha : vec3(0.0);
    vec3 disp = vec3(linearToSrgb(toneCurve(straight.r, kToneCurveAcesFitted)),
                     linearToSrgb(toneCurve(straight.g, kToneCurveAcesFitted)),
                     linearToSrgb(toneCurve(straight.b, kToneCurveAcesFitted)));
    c = vec4(disp * alpha, alpha);
  }
  o_colour = c;
}
