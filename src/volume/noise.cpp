// glsl/common/noise.glsl compiled as C++ in float, as the GPU runs it (core/glsl_cpp.h).
#include "volume/noise.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "core/glsl_cpp.h"

namespace nph::volume {

namespace noise_f32 {
using namespace nph::glsl;
using Number = float;
#include "../glsl/common/noise.glsl"
}  // namespace noise_f32

glm::vec4 noiseTexelFloat(int i, int j, int k) { return noise_f32::noiseTexel(glm::ivec3(i, j, k), kNoiseTexels); }

std::uint8_t unormCode(float v) {
  return static_cast<std::uint8_t>(std::lround(double(std::clamp(v, 0.0f, 1.0f)) * 255.0));
}

glm::dvec4 NoiseVolume::texel(int i, int j, int k) const {
  const std::size_t t = 4 * ((std::size_t(k) * kNoiseTexels + std::size_t(j)) * kNoiseTexels + std::size_t(i));
  return glm::dvec4(rgba[t], rgba[t + 1], rgba[t + 2], rgba[t + 3]) / 255.0;
}

namespace {

// GL_LINEAR with GL_REPEAT on one level of size³ RGBA8 texels.
glm::dvec4 sampleLevel(const std::vector<std::uint8_t>& rgba, int size, const glm::dvec3& q) {
  const glm::dvec3 c = q * double(size) - 0.5;  // texel centres at integers
  const glm::dvec3 fl = glm::floor(c);
  const glm::dvec3 t = c - fl;
  const auto wrap = [size](double x) {
    const long long n = size;
    return std::size_t(((static_cast<long long>(x) % n) + n) % n);
  };
  const auto n = std::size_t(size);
  glm::dvec4 r(0.0);
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const double w = (dx ? t.x : 1.0 - t.x) * (dy ? t.y : 1.0 - t.y) * (dz ? t.z : 1.0 - t.z);
        const std::size_t i = 4 * ((wrap(fl.z + dz) * n + wrap(fl.y + dy)) * n + wrap(fl.x + dx));
        r += w * glm::dvec4(rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]) / 255.0;
      }
  return r;
}

}  // namespace

glm::dvec4 NoiseVolume::sample(const glm::dvec3& q) const { return sampleLevel(rgba, kNoiseTexels, q); }

glm::dvec4 NoiseVolume::sampleLod(const glm::dvec3& q, double lod) const {
  const auto level = [&](int k) -> glm::dvec4 {
    return k == 0 ? sample(q) : sampleLevel(mips[std::size_t(k - 1)], kNoiseTexels >> k, q);
  };
  if (!(lod > 0.0)) return sample(q);
  const int last = kNoiseLevels - 1;
  if (lod >= double(last)) return level(last);
  const int d1 = int(std::floor(lod));
  const double f = lod - double(d1);
  return (1.0 - f) * level(d1) + f * level(d1 + 1);
}

std::vector<std::uint8_t> noiseMipLevel(const std::vector<std::uint8_t>& finer, int finer_size) {
  const auto n = std::size_t(finer_size), m = n / 2;
  std::vector<std::uint8_t> out(4 * m * m * m);
  for (std::size_t k = 0; k < m; ++k)
    for (std::size_t j = 0; j < m; ++j)
      for (std::size_t i = 0; i < m; ++i)
        for (std::size_t ch = 0; ch < 4; ++ch) {
          unsigned sum = 0;
          for (std::size_t d = 0; d < 8; ++d)
            sum += finer[4 * (((2 * k + (d >> 2)) * n + 2 * j + ((d >> 1) & 1)) * n + 2 * i + (d & 1)) + ch];
          out[4 * ((k * m + j) * m + i) + ch] = std::uint8_t((sum + 4) / 8);
        }
  return out;
}

std::vector<std::vector<std::uint8_t>> noiseMipChain(const std::vector<std::uint8_t>& level0) {
  std::vector<std::vector<std::uint8_t>> chain;
  chain.reserve(kNoiseLevels - 1);  // `finer` points into it
  const std::vector<std::uint8_t>* finer = &level0;
  for (int k = 1; k < kNoiseLevels; ++k) {
    chain.push_back(noiseMipLevel(*finer, kNoiseTexels >> (k - 1)));
    finer = &chain.back();
  }
  return chain;
}

namespace {

// Tile statistics of the texels (detail.glsl centres and scales each term with them). The terms
// combining two frames (n1 at q, n2 at a rotated, finer q) treat the frames as independent: the
// mean of a sum/product is the sum/product of the means; the half range bounds every value the
// interpolated channels can take (each channel stays within its texels' [min, max]).
NoiseStats measure(const std::vector<std::uint8_t>& rgba) {
  const std::size_t n = rgba.size() / 4;
  glm::dvec4 sum(0.0), lo(1.0), hi(0.0);
  double sumRG = 0.0;
  for (std::size_t t = 0; t < n; ++t) {
    const glm::dvec4 v = glm::dvec4(rgba[4 * t], rgba[4 * t + 1], rgba[4 * t + 2], rgba[4 * t + 3]) / 255.0;
    sum += v;
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
    sumRG += v.r * v.g;
  }
  const glm::dvec4 mean = sum / double(n);
  const auto term = [](double m, double a, double b) { return NoiseTermStats{m, std::max({m - a, b - m, 1e-6})}; };
  NoiseStats s;
  s.r = term(mean.r, lo.r, hi.r);
  s.g = term(mean.g, lo.g, hi.g);
  s.a = term(mean.a, lo.a, hi.a);
  s.stratiform = term(mean.r + mean.a, lo.r + lo.a, hi.r + hi.a);
  s.convective = term(sumRG / double(n) * mean.b, lo.r * lo.g * lo.b, hi.r * hi.g * hi.b);
  return s;
}

NoiseVolume compute() {
  NoiseVolume v;
  const int n = kNoiseTexels;
  v.rgba.resize(std::size_t(4) * std::size_t(n) * std::size_t(n) * std::size_t(n));
  tbb::parallel_for(0, n, [&](int k) {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const glm::vec4 c = noiseTexelFloat(i, j, k);
        const std::size_t t =
            4 * ((std::size_t(k) * std::size_t(n) + std::size_t(j)) * std::size_t(n) + std::size_t(i));
        for (int ch = 0; ch < 4; ++ch) v.rgba[t + std::size_t(ch)] = unormCode(c[ch]);
      }
  });
  v.stats = measure(v.rgba);
  v.mips = noiseMipChain(v.rgba);
  return v;
}

}  // namespace

const NoiseVolume& noiseVolume() {
  static const NoiseVolume v = compute();
  return v;
}

}  // namespace nph::volume
