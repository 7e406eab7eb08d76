// The cubic B-spline shared by the shaders and the CPU (glsl/common/cubic_bspline.glsl, compiled
// as C++ by volume/reconstruction.h): its weights against the closed form of the uniform cubic
// B-spline's basis, and the shaders' merge into two linear fetches against the CPU's 64-weight sum.
#include <array>
#include <cmath>

#include <gtest/gtest.h>

#include "volume/reconstruction.h"

namespace nph::volume {
namespace {

/// The uniform cubic B-spline basis B(t) (support |t| < 2), the closed form the weights sample:
/// the weight of the sample at offset d from the point is B(d).
double bspline(double t) {
  t = std::abs(t);
  if (t < 1.0) return 2.0 / 3.0 - t * t + 0.5 * t * t * t;
  if (t < 2.0) return (2.0 - t) * (2.0 - t) * (2.0 - t) / 6.0;
  return 0.0;
}

TEST(CubicBSpline, WeightsAreTheBasisSampledAtTheFourOffsets) {
  for (int n = 0; n <= 64; ++n) {
    const double f = n / 64.0;
    const std::array<double, 4> w = cubicBSplineWeights(f);
    double sum = 0.0;
    for (int t = 0; t < 4; ++t) {
      EXPECT_NEAR(w[std::size_t(t)], bspline(f - (t - 1)), 1e-15) << "f " << f << " tap " << t;
      EXPECT_GE(w[std::size_t(t)], 0.0);
      sum += w[std::size_t(t)];
    }
    EXPECT_NEAR(sum, 1.0, 1e-15) << "f " << f;  // partition of unity
  }
}

/// What the shaders compute on one axis: two linear fetches of s at c₁ − 1 + h0 and c₁ + 1 + h1,
/// weighted g0 and g1 — against the 4-tap sum the CPU evaluates, for samples of any sign.
TEST(CubicBSpline, TwoLinearFetchesEqualTheFourTapSum) {
  const std::array<double, 4> s = {3.0, -1.5, 7.25, 0.5};  // samples c₁ − 1 … c₁ + 2
  for (int n = 0; n <= 64; ++n) {
    const double f = n / 64.0;
    const std::array<double, 4> w = cubicBSplineWeights(f);
    const glm::dvec4 m = cubicBSplineFetches(f);  // (g0, g1, h0, h1)
    ASSERT_GE(m.x, 1.0 / 6.0 - 1e-15);
    ASSERT_GE(m.y, 1.0 / 6.0 - 1e-15);
    ASSERT_TRUE(m.z >= 0.0 && m.z <= 1.0 && m.w >= 0.0 && m.w <= 1.0) << "fetches stay between their two samples";
    const double fetch0 = (1.0 - m.z) * s[0] + m.z * s[1], fetch1 = (1.0 - m.w) * s[2] + m.w * s[3];
    const double four = w[0] * s[0] + w[1] * s[1] + w[2] * s[2] + w[3] * s[3];
    EXPECT_NEAR(m.x * fetch0 + m.y * fetch1, four, 1e-14) << "f " << f;
  }
}

/// reconstructAt's cubic sum reproduces a polynomial of degree ≤ 1 exactly, in 3-D, at any point
/// (the B-spline's linear precision), with the shared weights.
TEST(CubicBSpline, TheCpuSumReproducesALinearField) {
  auto field = [](int i, int j, int k) { return 0.5 + 2.0 * i - 3.0 * j + 0.25 * k; };
  for (const glm::dvec3 c : {glm::dvec3(4.3, 5.9, 2.0), glm::dvec3(7.0, 3.25, 6.75), glm::dvec3(5.5, 5.5, 5.5)}) {
    EXPECT_NEAR(reconstructAt(Reconstruction::Cubic, c, field), 0.5 + 2.0 * c.x - 3.0 * c.y + 0.25 * c.z, 1e-12);
  }
}

}  // namespace
}  // namespace nph::volume
