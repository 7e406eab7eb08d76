// The deep light map's look-up between texels (Nes 2008 §5.4.2: the light at any point is
// interpolated from the light functions of the surrounding texels): the four texels around the
// light-space point (lu, lv) are evaluated at depth s and blended bilinearly, clamped to the edge
// texels like GL_CLAMP_TO_EDGE; outside the map's u/v footprint the point is in full sunlight (1).
// Written once in the GLSL subset of core/glsl_cpp.h (issue 17 item 4): glsl/dlm/lookup.glsl
// includes it (Number = float), lighting/light_space.h's blendTexels (Number = double) — the CPU
// twin of the eye pass's look-up and of the reference DLM.
//
// The includer defines LF_TEXEL(a, b, s): texel (a, b)'s light function at depth s.
// texel_u, texel_v: texel size [m]; nu, nv: texels along u and v.

#if !defined(NPH_GLSL_AS_CPP) && !defined(Number)
#define Number float
#endif

Number lightBlend(Number lu, Number lv, Number s, Number texel_u, Number texel_v, int nu, int nv) {
  if (lu < Number(0.0) || lv < Number(0.0) || lu > texel_u * Number(nu) || lv > texel_v * Number(nv))
    return Number(1.0);
  Number tu = lu / texel_u - Number(0.5);
  Number tv = lv / texel_v - Number(0.5);
  Number u0 = floor(tu);
  Number v0 = floor(tv);
  Number fu = tu - u0;
  Number fv = tv - v0;
  int a0 = clamp(int(u0), 0, nu - 1);
  int a1 = clamp(int(u0) + 1, 0, nu - 1);
  int b0 = clamp(int(v0), 0, nv - 1);
  int b1 = clamp(int(v0) + 1, 0, nv - 1);
  Number a = LF_TEXEL(a0, b0, s);
  Number b = LF_TEXEL(a1, b0, s);
  Number c = LF_TEXEL(a0, b1, s);
  Number d = LF_TEXEL(a1, b1, s);
  return mix(mix(a, b, fu), mix(c, d, fu), fv);
}
