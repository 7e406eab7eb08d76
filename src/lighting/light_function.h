#pragma once
// A deep light map texel's light function I(s): piecewise linear through nodes (s, I), constant
// before the first and after the last node (Nes 2008 §5.3.1-5.3.2, Table 5.2).
//
// Compression (Nes 2008 §5.3.4, Algorithm 2, eq. 5.14-5.17, after Lokovic & Veach 2000): nodes
// are a subset of the samples; a segment from node P is extended over samples c as long as the
// slope P→c stays inside the intersection of every intermediate sample's slope window
// [(I_c − ε − I_P)/(s_c − s_P), (I_c + ε − I_P)/(s_c − s_P)]. When a sample falls outside, the
// previous sample becomes the next node. Contract: at every sample the stored function is within
// ε of the sample; since both the sampled and the stored function are linear between samples,
// the bound holds for all s. The window arithmetic is written once, in
// glsl/common/light_compress.glsl: the DLM pass (glsl/dlm/compress.glsl) runs it in float, this
// class (the test oracle) compiles it as C++ in double (core/glsl_cpp.h).
#include <vector>

namespace nph::lighting {

struct LightNode {
  float depth_m;
  float intensity;
};

/// The compressor's window between samples (glsl/common/light_compress.glsl's CompressorWindow).
struct CompressorState {
  double nodeS = 0, nodeI = 0, prevS = 0, prevI = 0;
  double lo = 0, hi = 0;
  bool haveBounds = false;
};

/// Incremental compressor: push samples in increasing depth, then finish(). The final sample is
/// a node unless the last segment is exactly flat at the last node's value (then the constant
/// extrapolation past the last node already represents it): an empty ray is a single node.
class LightFunctionCompressor {
 public:
  explicit LightFunctionCompressor(double epsilon) : eps_(epsilon) {}
  void push(double depth_m, double intensity);
  /// Emits the last sample as the final node and returns the node list.
  std::vector<LightNode> finish();

 private:
  double eps_;
  std::vector<LightNode> nodes_;
  bool havePrev_ = false;
  CompressorState state_;
};

std::vector<LightNode> compressLightFunction(const std::vector<double>& depth_m, const std::vector<double>& intensity,
                                             double epsilon);

/// I(s) of a node list (linear interpolation; constant beyond both ends): the eye pass's function,
/// glsl/common/light_function.glsl, compiled as C++ in double (core/glsl_cpp.h).
double evaluateLightFunction(const LightNode* nodes, int count, double depth_m);

}  // namespace nph::lighting
