#include "cache/quantize.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "core/error.h"

namespace nph::cache {

void quantise(std::span<const float> values, float max_value, std::span<std::uint16_t> out) {
  if (values.size() != out.size()) throw UsageError("quantise: input and output sizes differ");
  if (!(max_value > 0.0f)) {  // empty (or all non-positive) volume
    for (auto& q : out) q = 0;
    return;
  }
  const double inv_scale = kQuantisationLevels / double(max_value);
  for (std::size_t n = 0; n < values.size(); ++n) {
    const double v = double(values[n]);
    double q = std::nearbyint(v * inv_scale);  // round half to even; error <= 0.5 either way
    if (!(q > 0.0)) q = 0.0;                   // also maps NaN to 0 (callers reject NaN earlier)
    if (q > kQuantisationLevels) q = kQuantisationLevels;
    out[n] = static_cast<std::uint16_t>(q);
  }
}

void dequantise(std::span<const std::uint16_t> codes, float max_value, std::span<float> out) {
  if (codes.size() != out.size()) throw UsageError("dequantise: input and output sizes differ");
  const double scale = max_value > 0.0f ? double(max_value) / kQuantisationLevels : 0.0;
  for (std::size_t n = 0; n < codes.size(); ++n) out[n] = static_cast<float>(double(codes[n]) * scale);
}

std::size_t quantiseWind(std::span<const float> values, std::span<std::int16_t> out) {
  if (values.size() != out.size()) throw UsageError("quantiseWind: input and output sizes differ");
  std::size_t non_finite = 0;
  for (std::size_t n = 0; n < values.size(); ++n) {
    const double u = double(values[n]);
    if (!std::isfinite(u)) {
      out[n] = 0;
      ++non_finite;
      continue;
    }
    const double q = std::clamp(std::nearbyint(u / kWindStep_m_per_s), -kWindMaxCode, kWindMaxCode);
    out[n] = static_cast<std::int16_t>(q);
  }
  return non_finite;
}

void dequantiseWind(std::span<const std::int16_t> codes, std::span<float> out) {
  if (codes.size() != out.size()) throw UsageError("dequantiseWind: input and output sizes differ");
  for (std::size_t n = 0; n < codes.size(); ++n) out[n] = static_cast<float>(double(codes[n]) * kWindStep_m_per_s);
}

void packWindCodes(std::span<const std::int16_t> codes, std::size_t row, std::span<std::byte> out) {
  if (out.size() != 2 * codes.size() || row == 0 || codes.size() % row != 0) {
    throw UsageError("packWindCodes: sizes do not fit");
  }
  const std::size_t n = codes.size();
  for (std::size_t start = 0; start < n; start += row) {
    std::uint16_t before = 0;
    for (std::size_t q = start; q < start + row; ++q) {
      const auto code = static_cast<std::uint16_t>(codes[q]);
      const auto d = static_cast<std::uint16_t>(code - before);  // mod 2^16
      before = code;
      // zigzag: the sign bit (bit 15) to bit 0
      const auto z = static_cast<std::uint16_t>(static_cast<std::uint16_t>(d << 1) ^ ((d & 0x8000u) ? 0xffffu : 0u));
      out[q] = static_cast<std::byte>(z >> 8);
      out[n + q] = static_cast<std::byte>(z & 0xffu);
    }
  }
}

void unpackWindCodes(std::span<const std::byte> packed, std::size_t row, std::span<std::int16_t> codes) {
  if (packed.size() != 2 * codes.size() || row == 0 || codes.size() % row != 0) {
    throw UsageError("unpackWindCodes: sizes do not fit");
  }
  const std::size_t n = codes.size();
  for (std::size_t start = 0; start < n; start += row) {
    std::uint16_t before = 0;
    for (std::size_t q = start; q < start + row; ++q) {
      const auto z = static_cast<std::uint16_t>((std::to_integer<unsigned>(packed[q]) << 8) |
                                                std::to_integer<unsigned>(packed[n + q]));
      const auto d = static_cast<std::uint16_t>((z >> 1) ^ ((z & 1u) ? 0xffffu : 0u));
      before = static_cast<std::uint16_t>(before + d);
      codes[q] = static_cast<std::int16_t>(before);
    }
  }
}

}  // namespace nph::cache
