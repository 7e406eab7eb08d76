// Online ε-bounded compression of a light function into nodes (s, I) — Nes 2008 §5.3.4,
// Algorithm 2, eq. 5.14-5.17, after Lokovic & Veach 2000. Line-by-line twin of
// lighting/light_function.cpp (the CPU oracle of the tests); see there for the error argument.
// The node list of texel (a, b) lives in layers 0 … count−1 of u_nodes (RG32F: depth, intensity).
layout(rg32f, binding = IMAGE_DLM_NODES) uniform image3D u_nodes;
uniform int u_max_nodes;
uniform float u_epsilon;

struct Compressor {
  ivec2 texel;
  int count;        // nodes written
  bool overflow;    // a node did not fit (see emitNode)
  float nodeS, nodeI, prevS, prevI, lo, hi;
  bool haveBounds;
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
  c.nodeS = s; c.nodeI = I; c.prevS = s; c.prevI = I;
  c.lo = 0.0; c.hi = 0.0;
  c.haveBounds = false;
  emitNode(c, s, I);  // the first sample is always a node
  return c;
}

void pushSample(inout Compressor c, float s, float I) {
  float ds = s - c.nodeS;
  float slope = (I - c.nodeI) / ds;
  float up = (I + u_epsilon - c.nodeI) / ds;  // eq. 5.14
  float dn = (I - u_epsilon - c.nodeI) / ds;  // eq. 5.15
  if (!c.haveBounds) {
    c.lo = dn; c.hi = up; c.haveBounds = true;
  } else if (slope > c.hi || slope < c.lo) {
    emitNode(c, c.prevS, c.prevI);
    c.nodeS = c.prevS; c.nodeI = c.prevI;
    float ds2 = s - c.nodeS;
    c.lo = (I - u_epsilon - c.nodeI) / ds2;
    c.hi = (I + u_epsilon - c.nodeI) / ds2;
  } else {
    c.lo = max(c.lo, dn); c.hi = min(c.hi, up);
  }
  c.prevS = s; c.prevI = I;
}

// Returns the node count (the final sample is a node unless the tail is exactly flat).
int finishCompressor(inout Compressor c) {
  bool flatTail = c.prevI == c.nodeI && (!c.haveBounds || (c.lo <= 0.0 && c.hi >= 0.0));
  bool hasTail = c.prevS != c.nodeS || c.count == 0;
  if (hasTail && !flatTail) {
    int slot = min(c.count, u_max_nodes - 1);
    imageStore(u_nodes, ivec3(c.texel, slot), vec4(c.prevS, c.prevI, 0.0, 0.0));
    c.count = slot + 1;
  }
  return c.count;
}
