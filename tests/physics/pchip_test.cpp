#include "physics/pchip.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace nph::physics {
namespace {

double evalAt(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& d, double xq) {
  std::size_t k = 0;
  while (k + 2 < x.size() && xq >= x[k + 1]) ++k;
  return pchipEvaluate(x, y, d, k, xq);
}

std::vector<double> nonUniformNodes(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> step(20.0, 900.0);
  std::vector<double> x{37.0};
  for (int k = 1; k < n; ++k) x.push_back(x.back() + step(rng));
  return x;
}

TEST(Pchip, ExactOnLinearData) {
  std::mt19937 rng(1);
  const std::vector<double> x = nonUniformNodes(rng, 12);
  std::vector<double> y, d(x.size());
  for (double xi : x) y.push_back(3.5 - 0.002 * xi);
  pchipSlopes(x, y, d);
  for (double di : d) EXPECT_NEAR(di, -0.002, 1e-15);
  for (double xq = x.front(); xq <= x.back(); xq += 7.3) {
    EXPECT_NEAR(evalAt(x, y, d, xq), 3.5 - 0.002 * xq, 1e-12);
  }
}

TEST(Pchip, InterpolatesNodes) {
  const std::vector<double> x{0, 1, 3, 4, 10}, y{0, 2, 1, 5, 5};
  std::vector<double> d(x.size());
  pchipSlopes(x, y, d);
  for (std::size_t k = 0; k + 1 < x.size(); ++k) {
    EXPECT_NEAR(pchipEvaluate(x, y, d, k, x[k]), y[k], 1e-14);
    EXPECT_NEAR(pchipEvaluate(x, y, d, k, x[k + 1]), y[k + 1], 1e-14);
  }
  // by hand: secants (2, -0.5, 4, 0) change sign or vanish at every interior node, so
  // d = (d0, 0, 0, 0, 0) with the end formula d0 = ((2·1 + 2)·2 - 1·(-0.5)) / 3 = 8.5/3;
  // at t = 1/2 the Hermite basis is (1/2, 1/8, 1/2, -1/8).
  EXPECT_NEAR(d[0], 8.5 / 3.0, 1e-15);
  EXPECT_NEAR(evalAt(x, y, d, 0.5), 0.125 * 8.5 / 3.0 + 1.0, 1e-12);
  EXPECT_NEAR(evalAt(x, y, d, 2.0), 1.5, 1e-12);
  EXPECT_NEAR(evalAt(x, y, d, 3.5), 3.0, 1e-12);
  EXPECT_NEAR(evalAt(x, y, d, 7.0), 5.0, 1e-12);
}

TEST(Pchip, MonotoneDataGiveMonotoneInterpolant) {
  std::mt19937 rng(2);
  std::exponential_distribution<double> jump(1.0);
  std::bernoulli_distribution flat(0.3);
  for (int trial = 0; trial < 50; ++trial) {
    const std::vector<double> x = nonUniformNodes(rng, 15);
    std::vector<double> y{0.0}, d(x.size());
    for (std::size_t k = 1; k < x.size(); ++k) y.push_back(y.back() + (flat(rng) ? 0.0 : jump(rng)));
    pchipSlopes(x, y, d);
    double prev = -1.0;
    for (double xq = x.front(); xq <= x.back(); xq += 3.1) {
      const double v = evalAt(x, y, d, xq);
      EXPECT_GE(v, prev - 1e-12) << "trial " << trial << " x " << xq;
      prev = v;
    }
  }
}

TEST(Pchip, NoOvershootAtACloudEdge) {
  // a cloud layer: zero, a steep jump, a plateau, zero again (non-negative data)
  const std::vector<double> x{0, 300, 700, 1200, 1800, 2500, 3300}, y{0, 0, 0.05, 0.06, 0.06, 0, 0};
  std::vector<double> d(x.size());
  pchipSlopes(x, y, d);
  for (double xq = 0; xq <= 3300; xq += 1.0) {
    const double v = evalAt(x, y, d, xq);
    EXPECT_GE(v, 0.0) << xq;
    EXPECT_LE(v, 0.06 + 1e-15) << xq;
    if (xq <= 300 || xq >= 2500) {
      EXPECT_EQ(v, 0.0) << xq;  // no ringing into clear air
    }
  }
}

}  // namespace
}  // namespace nph::physics
