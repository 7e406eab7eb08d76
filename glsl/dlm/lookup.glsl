// Deep light map look-up (Nes 2008 §5.3.2 last paragraph, §5.4.2): the light intensity at any
// world point, shared by the ray caster, the ground-shadow code and the scatter-map pass.
// Requires dlm/light_space.glsl. Each texel's function is evaluated by a linear scan of its node
// list (issue 19); the four texels around the point are blended bilinearly. Points outside the
// map's u/v footprint are in full sunlight (1); before the first node / after the last node the
// function is constant (so a point below the volume gets the transmittance through it: ground
// shadows).
//
// The light function and the blend are written once with their CPU twins (core/glsl_cpp.h):
// glsl/common/light_function.glsl (the scan, and why it is linear) and glsl/common/light_blend.glsl.
layout(binding = UNIT_DLM_NODES) uniform sampler3D u_dlm_nodes;  // RG32F: (depth, intensity) per layer
layout(binding = UNIT_DLM_COUNTS) uniform usampler2D u_dlm_counts;  // count | DLM_COUNT_UNBOUNDED

#define LF_NODES ivec2 t
#define LF_NODE(k) texelFetch(u_dlm_nodes, ivec3(t, (k)), 0).rg
#include "common/light_function.glsl"

float dlmEvaluateTexel(ivec2 t, float s) {
  if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(t, u_ls_texels))) return 1.0;
  return lightFunctionAt(t, int(texelFetch(u_dlm_counts, t, 0).r & DLM_COUNT_MASK), s);
}

#define LF_TEXEL(a, b, s) dlmEvaluateTexel(ivec2((a), (b)), (s))
#include "common/light_blend.glsl"

// Light intensity at light-space position l (metres along u, v, w).
float dlmIntensityLight(vec3 l) {
  return lightBlend(l.x, l.y, l.z, u_ls_texel_m.x, u_ls_texel_m.y, u_ls_texels.x, u_ls_texels.y);
}

float dlmIntensity(vec3 world_m) { return dlmIntensityLight(lightFromWorld(world_m)); }
