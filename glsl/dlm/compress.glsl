// Online ε-bounded compression of a light function into nodes (s, I) — Nes 2008 §5.3.4,
// Algorithm 2, eq. 5.14-5.17, after Lokovic & Veach 2000. The window arithmetic is
// common/light_compress.glsl, which lighting/light_function.cpp (the CPU oracle of the tests)
// compiles as C++; this file adds the node storage of the GPU.
// The node list of texel (a, b) lives in layers 0 … count−1 of u_nodes (RG32F: depth, intensity).
layout(rg32f, binding = IMAGE_DLM_NODES) uniform image3D u_nodes;
uniform int u_max_nodes;
uniform float u_epsilon;

#include "common/light_compress.glsl"

struct Compressor {
  ivec2 texel;
  int count;           // nodes written
  bool overflow;       // a node did not fit (see emitNode)
  CompressorWindow w;  // the ε window (common/light_compress.glsl, shared with the CPU oracle)
};

// Writes a node; when the budget is full the node is dropped and the texel flagged: the last slot
// is reserved for the ray's final sample (written by finishCompressor), so even an overflowed
// texel ends at the right intensity — but its ε bound is not kept (the builder then retries it
// with a doubled ε, see render/dlm/deep_light_map.cpp).
void emitNode(inout Compressor c, float s, float I) {
  if (c.count < u_max_nodes - 1) {
    imageStore(u_nodes, ivec3(c.texel, c.count), vec4(s, I, 0.0, 0.0));
    c.count++;
  } else {
    c.overflow = true;
  }
}

Compressor startCompressor(ivec2 texel, float s, float I) {
  Compressor c;
  c.texel = texel;
  c.count = 0;
  c.overflow = false;
  c.w = openWindow(s, I);
  emitNode(c, s, I);  // the first sample is always a node
  return c;
}

void pushSample(inout Compressor c, float s, float I) {
  c.w = windowPush(c.w, s, I, u_epsilon);
  if (c.w.emitted) emitNode(c, c.w.nodeS, c.w.nodeI);
}

// Returns the node count (the final sample is a node unless the tail is exactly flat).
int finishCompressor(inout Compressor c) {
  bool hasTail = c.w.prevS != c.w.nodeS || c.count == 0;
  if (hasTail && !windowFlatTail(c.w)) {
    int slot = min(c.count, u_max_nodes - 1);
    imageStore(u_nodes, ivec3(c.texel, slot), vec4(c.w.prevS, c.w.prevI, 0.0, 0.0));
    c.count = slot + 1;
  }
  return c.count;
}
