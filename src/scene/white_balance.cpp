#include "scene/white_balance.h"

#include <cmath>

#include <fmt/format.h>

#include "core/error.h"

namespace nph::scene {

glm::dvec2 planckianXy(double kelvin) {
  // Kang et al. 2002, eqs. for x_c (two cubics in 1/T) and y_c (three cubics in x_c).
  const double t = kelvin, t2 = t * t, t3 = t2 * t;
  const double x = t <= 4000.0 ? -0.2661239e9 / t3 - 0.2343589e6 / t2 + 0.8776956e3 / t + 0.179910
                               : -3.0258469e9 / t3 + 2.1070379e6 / t2 + 0.2226347e3 / t + 0.240390;
  const double x2 = x * x, x3 = x2 * x;
  const double y = t <= 2222.0   ? -1.1063814 * x3 - 1.34811020 * x2 + 2.18555832 * x - 0.20219683
                   : t <= 4000.0 ? -0.9549476 * x3 - 1.37418593 * x2 + 2.09137015 * x - 0.16748867
                                 : 3.0817580 * x3 - 5.87338670 * x2 + 3.75112997 * x - 0.37001483;
  return {x, y};
}

namespace {

// The locus moved onto D65 (CIE 15:2004, (0.3127, 0.3290) as IEC 61966-2-1 rounds it) at 6504 K.
glm::dvec2 movedLocusXy(double kelvin) {
  return planckianXy(kelvin) + (glm::dvec2(0.3127, 0.3290) - planckianXy(kNeutralWhiteBalanceK));
}

// CIE 1960 UCS: u = 4x / (−2x + 12y + 3), v = 6y / (−2x + 12y + 3), and back.
glm::dvec2 uvOfXy(glm::dvec2 xy) { return glm::dvec2(4.0 * xy.x, 6.0 * xy.y) / (-2.0 * xy.x + 12.0 * xy.y + 3.0); }
glm::dvec2 xyOfUv(glm::dvec2 uv) { return glm::dvec2(3.0 * uv.x, 2.0 * uv.y) / (2.0 * uv.x - 8.0 * uv.y + 4.0); }

}  // namespace

glm::dvec3 whiteBalanceLight(double kelvin, double duv) {
  glm::dvec2 xy = movedLocusXy(kelvin);
  if (duv != 0.0) {
    // The locus's tangent in uv by a central difference (0.1 % of T either way), its normal turned
    // towards +v (above the locus: green).
    const glm::dvec2 tangent = uvOfXy(movedLocusXy(kelvin * 1.001)) - uvOfXy(movedLocusXy(kelvin / 1.001));
    glm::dvec2 normal = glm::normalize(glm::dvec2(-tangent.y, tangent.x));
    if (normal.y < 0.0) normal = -normal;
    xy = xyOfUv(uvOfXy(xy) + duv * normal);
  }
  const glm::dvec3 xyz{xy.x / xy.y, 1.0, (1.0 - xy.x - xy.y) / xy.y};
  // XYZ → linear Rec.709 (IEC 61966-2-1 with D65 at (0.3127, 0.3290); scene/ocio/config.ocio).
  return {3.2409699419 * xyz.x - 1.5373831776 * xyz.y - 0.4986107603 * xyz.z,
          -0.9692436363 * xyz.x + 1.8759675015 * xyz.y + 0.0415550574 * xyz.z,
          0.0556300797 * xyz.x - 0.2039769589 * xyz.y + 1.0569715142 * xyz.z};
}

glm::dvec3 whiteBalanceGain(double kelvin, double duv) {
  if (!(kelvin >= kMinWhiteBalanceK && kelvin <= kMaxWhiteBalanceK)) {
    throw UsageError(fmt::format("white balance {} K: expected {}–{} K", kelvin, kMinWhiteBalanceK, kMaxWhiteBalanceK));
  }
  if (!(std::abs(duv) <= kMaxWhiteBalanceDuv)) {
    throw UsageError(fmt::format("white balance tint Duv {}: expected within ±{}", duv, kMaxWhiteBalanceDuv));
  }
  // The neutral setting is the identity by construction, not by computing P(T_ref) twice: clang
  // (-ffp-contract=on, its default) emits a·b + c as llvm.fmuladd, "multiply-add expressions that
  // can be fused if the code generator determines that (a) the target instruction set has support
  // for a fused operation" (LLVM LangRef). The optimiser folds the call with the constant T_ref
  // fused (one rounding); the call at run time rounds twice on x86-64 without FMA. P(T_ref) /
  // P(T_ref) came out as (1 − 2⁻⁵², 1, 1 − 2⁻⁵³) in the clang sanitizer build
  // (docs/reliability.md "Session 20 run").
  if (kelvin == kNeutralWhiteBalanceK && duv == 0.0) return glm::dvec3(1.0);
  return whiteBalanceLight(kNeutralWhiteBalanceK) / whiteBalanceLight(kelvin, duv);
}

}  // namespace nph::scene
