// One texel's light function I(s) from its compressed node list (Nes 2008 §5.3.2 last paragraph:
// piecewise-linear between the nodes the compressor kept, §5.3.4; constant before the first and
// after the last node, so a point below the volume gets the transmittance through it). Written once
// in the GLSL subset of core/glsl_cpp.h (issue 17 item 4): glsl/dlm/lookup.glsl includes it with the
// nodes in textures (Number = float), lighting/light_function.cpp with a node array (Number =
// double) for the CPU twin and the tests' oracle — one look-up, not two copies.
//
// The includer defines
//   LF_NODES    the parameter that names one texel's node list (GLSL: ivec2 t; C++: a pointer)
//   LF_NODE(k)  node k as vec2(depth [m], intensity)
//
// Why a linear scan (issue 19, "Frame time"): the light functions have few nodes (DeepLightMap::Stats
// mean_nodes; at most DlmSettings::max_nodes = 32), and llvmpipe runs 8 lanes in lock-step, so a
// binary search costs its full log₂(count) dependent fetches in every lane plus two more for the
// bracket, while the scan stops at the lanes' largest bracket index and reads each node once,
// keeping the bracket's (depth, intensity) pairs as it goes. Both find the same bracket — the last
// node with depth ≤ s and the next one — because the depths never decrease, so the result is
// bit-identical (ctest -R DlmLookupLinearScanIsBitIdentical). The binary search stays selectable
// with DLM_LOOKUP_BINARY_SEARCH, the baseline of tests/bench/frame_benchmark.cpp.

#if !defined(NPH_GLSL_AS_CPP) && !defined(Number)
#define Number float
#endif

Number lightFunctionAt(LF_NODES, int count, Number s) {
  if (count <= 0) return Number(1.0);
  vec2 first = LF_NODE(0);
  if (s <= Number(first.x)) return Number(first.y);
  vec2 last = LF_NODE(count - 1);
  if (s >= Number(last.x)) return Number(last.y);
#ifdef DLM_LOOKUP_BINARY_SEARCH
  int lo = 0;
  int hi = count - 1;  // depth[lo] <= s < depth[hi]
  while (hi - lo > 1) {
    int mid = (lo + hi) / 2;
    if (Number(LF_NODE(mid).x) <= s) lo = mid;
    else hi = mid;
  }
  vec2 a = LF_NODE(lo);
  vec2 b = LF_NODE(hi);
#else
  // depth[0] < s < depth[count − 1]: the scan stops at the first node deeper than s, at the latest
  // at count − 1 (the bound k < count only guards a malformed list).
  vec2 a = first;
  vec2 b = LF_NODE(1);
  for (int k = 2; Number(b.x) <= s && k < count; ++k) {
    a = b;
    b = LF_NODE(k);
  }
#endif
  Number f = b.x > a.x ? (s - Number(a.x)) / Number(b.x - a.x) : Number(0.0);
  return mix(Number(a.y), Number(b.y), f);
}
