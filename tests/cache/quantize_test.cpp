#include "cache/quantize.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

#include "core/error.h"

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

// The wind chunk's packing (packWindCodes) is a bijection: every int16, in rows, both neighbours
// of every wrap-around of the difference, comes back exactly; a row that rises by one code a
// column leaves a high-byte plane of zeros (what zstd then packs away).
TEST(Quantise, WindPackingIsExactAndSmoothRowsLeaveEmptyHighBytes) {
  std::vector<std::int16_t> codes;
  for (int c = -32768; c <= 32767; ++c) codes.push_back(static_cast<std::int16_t>(c));
  for (int c = 0; c < 256; ++c) codes.push_back(static_cast<std::int16_t>(c % 2 == 0 ? -32768 : 32767));
  std::vector<std::byte> packed(2 * codes.size());
  std::vector<std::int16_t> back(codes.size(), 7);
  packWindCodes(codes, 256, packed);
  unpackWindCodes(packed, 256, back);
  EXPECT_EQ(back, codes);
  // a smooth row: codes 100, 101, ... : differences 100 (first), then 1 -> zigzag 2: high bytes 0
  std::vector<std::int16_t> smooth(64);
  for (std::size_t i = 0; i < smooth.size(); ++i) smooth[i] = static_cast<std::int16_t>(100 + i);
  std::vector<std::byte> p(2 * smooth.size());
  packWindCodes(smooth, smooth.size(), p);
  for (std::size_t i = 0; i < smooth.size(); ++i) EXPECT_EQ(p[i], std::byte{0}) << i;
  EXPECT_EQ(p[smooth.size()], std::byte{200});            // zigzag(100)
  EXPECT_EQ(p[smooth.size() + 1], std::byte{2});          // zigzag(1)
  EXPECT_THROW(packWindCodes(smooth, 5, p), UsageError);  // 64 codes are no whole rows of 5
}

}  // namespace
}  // namespace nph::cache
