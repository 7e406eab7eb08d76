#include "lighting/light_space.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace nph::lighting {

void lightBasis(const glm::dvec3& lightDirection, glm::dvec3& u, glm::dvec3& v, glm::dvec3& w) {
  const double len = glm::length(lightDirection);
  if (!(len > 0.0) || !std::isfinite(len))
    throw UsageError("lightBasis: light direction must be a finite non-zero vector");
  w = lightDirection / len;
  // Reference "up" for u: world z unless the light is (nearly) vertical, then world y.
  const glm::dvec3 ref = std::abs(w.z) < 0.999 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
  u = glm::normalize(glm::cross(ref, w));
  v = glm::cross(w, u);
}

LightSpace fitLightSpace(const glm::dvec3& lightDirection, const glm::dvec3& boxMin, const glm::dvec3& boxMax,
                         glm::dvec2 texelSize_m, int maxTexels) {
  if (!(texelSize_m.x > 0.0) || !(texelSize_m.y > 0.0) || maxTexels < 1)
    throw UsageError("fitLightSpace: texel size and count must be positive");
  LightSpace ls;
  lightBasis(lightDirection, ls.u, ls.v, ls.w);
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 p((c & 1) ? boxMax.x : boxMin.x, (c & 2) ? boxMax.y : boxMin.y, (c & 4) ? boxMax.z : boxMin.z);
    const glm::dvec3 l(glm::dot(p, ls.u), glm::dot(p, ls.v), glm::dot(p, ls.w));
    lo = glm::min(lo, l);
    hi = glm::max(hi, l);
  }
  ls.origin_m = lo.x * ls.u + lo.y * ls.v + lo.z * ls.w;
  const glm::dvec2 extent(hi.x - lo.x, hi.y - lo.y);
  ls.depth_m = hi.z - lo.z;
  for (int i = 0; i < 2; ++i) {
    const double e = std::max(extent[i], texelSize_m[i]);  // a degenerate (flat) box still gets one texel
    // Clamp in double before the cast: with voxels of 1e-300 m the ratio is far beyond int
    // (undefined behaviour for the cast); NaN (a non-finite box) is refused.
    const double texels = std::ceil(e / texelSize_m[i] - 1e-9);
    if (std::isnan(texels)) throw UsageError("fitLightSpace: the box or the texel size is not finite");
    const int n = static_cast<int>(std::clamp(texels, 1.0, double(maxTexels)));
    ls.texels[i] = n;
    ls.extent_m[i] = e;
  }
  return ls;
}

glm::dvec2 lightTexelSize(const LightSpace& basis, const glm::dvec3& voxelSize_m, double texelVoxels) {
  const glm::dvec3 au = glm::abs(basis.u), av = glm::abs(basis.v);
  return glm::dvec2(glm::dot(au, voxelSize_m), glm::dot(av, voxelSize_m)) * texelVoxels;
}

}  // namespace nph::lighting
