// The slope window of the online ε-bounded light-function compressor — Nes 2008 §5.3.4,
// Algorithm 2, eq. 5.14–5.17, after Lokovic & Veach 2000 (the error argument is in
// src/lighting/light_function.h). Written once in the GLSL subset of core/glsl_cpp.h: the DLM
// pass includes it through glsl/dlm/compress.glsl (Number = float), the CPU oracle of the tests
// through lighting/light_function.cpp (Number = double) — one algorithm, not two copies.
//
// A segment starts at node (nodeS, nodeI) and is extended over samples c while the slope from the
// node to c stays inside the intersection [lo, hi] of every intermediate sample's window
//   [(I_c − ε − I_node)/(s_c − s_node), (I_c + ε − I_node)/(s_c − s_node)].
// When a sample falls outside, the previous sample becomes the next node.

#if !defined(NPH_GLSL_AS_CPP) && !defined(Number)
#define Number float
#endif

struct CompressorWindow {
  Number nodeS, nodeI;  // the open segment's first node
  Number prevS, prevI;  // the previous sample
  Number lo, hi;        // the slope window [lo, hi]
  bool haveBounds;      // false until a sample after the node has been seen
  bool emitted;         // set by windowPush: the previous sample became the node (nodeS, nodeI)
};

// The window of a ray whose first sample (s, I) is its first node.
CompressorWindow openWindow(Number s, Number I) {
  CompressorWindow w;
  w.nodeS = s;
  w.nodeI = I;
  w.prevS = s;
  w.prevI = I;
  w.lo = Number(0.0);
  w.hi = Number(0.0);
  w.haveBounds = false;
  w.emitted = false;
  return w;
}

// Feeds the next sample (s, I), s increasing. When the returned window has `emitted`, its
// (nodeS, nodeI) — the sample before this one — is a new node the caller must store.
CompressorWindow windowPush(CompressorWindow w, Number s, Number I, Number eps) {
  Number ds = s - w.nodeS;
  Number slope = (I - w.nodeI) / ds;
  Number up = (I + eps - w.nodeI) / ds;  // eq. 5.14
  Number dn = (I - eps - w.nodeI) / ds;  // eq. 5.15
  w.emitted = false;
  if (!w.haveBounds) {
    w.lo = dn;
    w.hi = up;
    w.haveBounds = true;
  } else if (slope > w.hi || slope < w.lo) {  // outside the window: close the segment at prev
    w.emitted = true;
    w.nodeS = w.prevS;
    w.nodeI = w.prevI;
    Number ds2 = s - w.nodeS;
    w.lo = (I - eps - w.nodeI) / ds2;
    w.hi = (I + eps - w.nodeI) / ds2;
  } else {  // eq. 5.16–5.17: narrow the window
    w.lo = max(w.lo, dn);
    w.hi = min(w.hi, up);
  }
  w.prevS = s;
  w.prevI = I;
  return w;
}

// True when the last segment is exactly flat at the node's value: the constant extrapolation past
// the last node already represents it, so the final sample need not be a node.
bool windowFlatTail(CompressorWindow w) {
  return w.prevI == w.nodeI && (!w.haveBounds || (w.lo <= Number(0.0) && w.hi >= Number(0.0)));
}
