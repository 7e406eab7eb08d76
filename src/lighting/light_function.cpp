#include "lighting/light_function.h"

#include <algorithm>

#include "core/error.h"

namespace nph::scene {

void LightFunctionCompressor::push(double s, double I) {
  if (nodes_.empty()) {  // the first sample is always a node
    nodes_.push_back({float(s), float(I)});
    nodeS_ = prevS_ = s;
    nodeI_ = prevI_ = I;
    return;
  }
  const double ds = s - nodeS_;
  const double slope = (I - nodeI_) / ds;
  const double up = (I + eps_ - nodeI_) / ds;  // eq. 5.14
  const double dn = (I - eps_ - nodeI_) / ds;  // eq. 5.15
  if (!haveBounds_) {
    lo_ = dn;
    hi_ = up;
    haveBounds_ = true;
  } else if (slope > hi_ || slope < lo_) {  // outside the segment's window: close it at prev
    nodes_.push_back({float(prevS_), float(prevI_)});
    nodeS_ = prevS_;
    nodeI_ = prevI_;
    const double ds2 = s - nodeS_;
    lo_ = (I - eps_ - nodeI_) / ds2;
    hi_ = (I + eps_ - nodeI_) / ds2;
  } else {
    lo_ = std::max(lo_, dn);
    hi_ = std::min(hi_, up);
  }
  prevS_ = s;
  prevI_ = I;
  havePrev_ = true;
}

std::vector<LightNode> LightFunctionCompressor::finish() {
  const bool flatTail = prevI_ == nodeI_ && (!haveBounds_ || (lo_ <= 0.0 && hi_ >= 0.0));
  if (havePrev_ && !flatTail) nodes_.push_back({float(prevS_), float(prevI_)});
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
  if (count <= 0) return 1.0;
  if (s <= double(nodes[0].depth_m)) return nodes[0].intensity;
  if (s >= double(nodes[count - 1].depth_m)) return nodes[count - 1].intensity;
  int lo = 0, hi = count - 1;  // invariant: depth[lo] <= s < depth[hi]
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (double(nodes[mid].depth_m) <= s) lo = mid;
    else hi = mid;
  }
  const double s0 = nodes[lo].depth_m, s1 = nodes[hi].depth_m;
  const double t = s1 > s0 ? (s - s0) / (s1 - s0) : 0.0;
  return double(nodes[lo].intensity) + t * (double(nodes[hi].intensity) - double(nodes[lo].intensity));
}

}  // namespace nph::scene
