// Deep light map look-up (Nes 2008 §5.3.2 last paragraph, §5.4.2): the light intensity at any
// world point, shared by the ray caster, the ground-shadow code and the scatter-map pass.
// Requires dlm/light_space.glsl. Each texel's function is evaluated by a linear scan of its node
// list (issue 19); the four texels around the point are blended bilinearly. Points outside the
// map's u/v footprint are in full sunlight (1); before the first node / after the last node the
// function is constant (so a point below the volume gets the transmittance through it: ground
// shadows).
//
// Why a linear scan (issue 19, "Frame time"): the light functions have few nodes (DeepLightMap::Stats
// mean_nodes; at most DlmSettings::max_nodes = 32), and llvmpipe runs 8 lanes in lock-step, so a binary
// search costs its full log₂(count) dependent fetches in every lane plus two more for the bracket,
// while the scan stops at the lanes' largest bracket index and reads each node once, keeping the
// bracket's (depth, intensity) pairs as it goes. Both find the same bracket — the last node with
// depth ≤ s and the next one — because the depths never decrease, so the result is bit-identical
// (ctest -R DlmLookupLinearScanIsBitIdentical). The binary search stays selectable with
// DLM_LOOKUP_BINARY_SEARCH, the baseline of tests/bench/frame_benchmark.cpp; the CPU twin
// (scene::evaluateLightFunction) keeps its binary search: same bracket, same arithmetic.
layout(binding = UNIT_DLM_NODES) uniform sampler3D u_dlm_nodes;  // RG32F: (depth, intensity) per layer
layout(binding = UNIT_DLM_COUNTS) uniform usampler2D u_dlm_counts;  // count | DLM_COUNT_UNBOUNDED

float dlmEvaluateTexel(ivec2 t, float s) {
  if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(t, u_ls_texels))) return 1.0;
  int count = int(texelFetch(u_dlm_counts, t, 0).r & DLM_COUNT_MASK);
  if (count <= 0) return 1.0;
  vec2 first = texelFetch(u_dlm_nodes, ivec3(t, 0), 0).rg;
  if (s <= first.x) return first.y;
  vec2 last = texelFetch(u_dlm_nodes, ivec3(t, count - 1), 0).rg;
  if (s >= last.x) return last.y;
#ifdef DLM_LOOKUP_BINARY_SEARCH
  int lo = 0, hi = count - 1;  // depth[lo] <= s < depth[hi]
  while (hi - lo > 1) {
    int mid = (lo + hi) / 2;
    if (texelFetch(u_dlm_nodes, ivec3(t, mid), 0).r <= s) lo = mid; else hi = mid;
  }
  vec2 a = texelFetch(u_dlm_nodes, ivec3(t, lo), 0).rg;
  vec2 b = texelFetch(u_dlm_nodes, ivec3(t, hi), 0).rg;
#else
  // depth[0] < s < depth[count − 1]: the scan stops at the first node deeper than s, at the latest
  // at count − 1 (the bound k < count only guards a malformed list).
  vec2 a = first, b = texelFetch(u_dlm_nodes, ivec3(t, 1), 0).rg;
  for (int k = 2; b.x <= s && k < count; ++k) {
    a = b;
    b = texelFetch(u_dlm_nodes, ivec3(t, k), 0).rg;
  }
#endif
  float f = b.x > a.x ? (s - a.x) / (b.x - a.x) : 0.0;
  return mix(a.y, b.y, f);
}

// Light intensity at light-space position l (metres along u, v, w).
float dlmIntensityLight(vec3 l) {
  vec2 t = l.xy / u_ls_texel_m - 0.5;
  vec2 t0 = floor(t);
  vec2 f = t - t0;
  ivec2 i0 = ivec2(t0);
  // Clamp to the edge texels inside the map (like GL_CLAMP_TO_EDGE); outside the footprint → 1.
  if (l.x < 0.0 || l.y < 0.0 || l.x > u_ls_texel_m.x * float(u_ls_texels.x) ||
      l.y > u_ls_texel_m.y * float(u_ls_texels.y)) return 1.0;
  ivec2 lo = clamp(i0, ivec2(0), u_ls_texels - 1);
  ivec2 hi = clamp(i0 + 1, ivec2(0), u_ls_texels - 1);
  float a = dlmEvaluateTexel(lo, l.z), b = dlmEvaluateTexel(ivec2(hi.x, lo.y), l.z);
  float c = dlmEvaluateTexel(ivec2(lo.x, hi.y), l.z), d = dlmEvaluateTexel(hi, l.z);
  return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

float dlmIntensity(vec3 world_m) { return dlmIntensityLight(lightFromWorld(world_m)); }
