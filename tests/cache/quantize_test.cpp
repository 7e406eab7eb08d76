#include "cache/quantize.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace nph::cache {
namespace {

TEST(Quantise, ErrorWithinDocumentedBoundOverManyMagnitudes) {
  std::mt19937 rng(7);
  for (float max_value : {1e-9f, 3.7e-5f, 0.02f, 1.0f, 123.0f}) {
    std::uniform_real_distribution<float> u(0.0f, max_value);
    std::vector<float> v(20000);
    for (auto& x : v) x = u(rng);
    v[0] = max_value;
    v[1] = 0.0f;
    v[2] = max_value * 0.5f / 65535.0f;  // exactly on a rounding boundary
    std::vector<std::uint16_t> q(v.size());
    std::vector<float> back(v.size());
    quantise(v, max_value, q);
    dequantise(q, max_value, back);
    const double bound = quantisationErrorBound(max_value);
    double worst = 0.0;
    for (std::size_t n = 0; n < v.size(); ++n) {
      worst = std::max(worst, std::abs(double(v[n]) - double(back[n])));
    }
    EXPECT_LE(worst, bound) << "max " << max_value;
    // The bound is tight: uniform data reaches at least 90 % of the rounding part.
    EXPECT_GT(worst, 0.9 * double(max_value) / 131070.0) << "max " << max_value;
    EXPECT_EQ(q[0], 65535);
    EXPECT_EQ(back[0], max_value);
    EXPECT_EQ(q[1], 0);
    EXPECT_EQ(back[1], 0.0f);
  }
}

TEST(Quantise, EmptyVolumeEncodesToZero) {
  std::vector<float> v(10, 0.0f), back(10, 1.0f);
  std::vector<std::uint16_t> q(10, 7);
  quantise(v, 0.0f, q);
  dequantise(q, 0.0f, back);
  for (std::size_t n = 0; n < v.size(); ++n) {
    EXPECT_EQ(q[n], 0);
    EXPECT_EQ(back[n], 0.0f);
  }
}

}  // namespace
}  // namespace nph::cache
