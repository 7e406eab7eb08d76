#include "lighting/light_function.h"

#include <algorithm>

#include "core/error.h"
#include "core/glsl_cpp.h"

namespace nph::lighting {

namespace f64 {  // the DLM pass's window arithmetic in double precision (core/glsl_cpp.h)
using namespace nph::glsl;
using Number = double;
#include "../glsl/common/light_compress.glsl"
// The look-up's light function, the nodes from an array (glsl/dlm/lookup.glsl reads a texture).
#define LF_NODES const LightNode* nodes
#define LF_NODE(k) vec2(nodes[k].depth_m, nodes[k].intensity)
#include "../glsl/common/light_function.glsl"
#undef LF_NODES
#undef LF_NODE
}  // namespace f64

namespace {

f64::CompressorWindow toWindow(const CompressorState& s) {
  return {s.nodeS, s.nodeI, s.prevS, s.prevI, s.lo, s.hi, s.haveBounds, false};
}
CompressorState fromWindow(const f64::CompressorWindow& w) {
  return {w.nodeS, w.nodeI, w.prevS, w.prevI, w.lo, w.hi, w.haveBounds};
}

}  // namespace

void LightFunctionCompressor::push(double s, double I) {
  if (nodes_.empty()) {  // the first sample is always a node
    nodes_.push_back({float(s), float(I)});
    state_ = fromWindow(f64::openWindow(s, I));
    return;
  }
  const f64::CompressorWindow w = f64::windowPush(toWindow(state_), s, I, eps_);
  if (w.emitted) nodes_.push_back({float(w.nodeS), float(w.nodeI)});  // closed at the previous sample
  state_ = fromWindow(w);
  havePrev_ = true;
}

std::vector<LightNode> LightFunctionCompressor::finish() {
  if (havePrev_ && !f64::windowFlatTail(toWindow(state_))) nodes_.push_back({float(state_.prevS), float(state_.prevI)});
  havePrev_ = false;
  return std::move(nodes_);
}

std::vector<LightNode> compressLightFunction(const std::vector<double>& s, const std::vector<double>& I,
                                             double epsilon) {
  if (s.size() != I.size()) throw UsageError("compressLightFunction: depth and intensity sizes differ");
  LightFunctionCompressor c(epsilon);
  for (std::size_t n = 0; n < s.size(); ++n) c.push(s[n], I[n]);
  return c.finish();
}

double evaluateLightFunction(const LightNode* nodes, int count, double s) {
  return f64::lightFunctionAt(nodes, count, s);
}

}  // namespace nph::lighting
