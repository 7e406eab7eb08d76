#pragma once
// 16-bit storage of extinction values (Nes 2008 §5.1.2: "scale up each value by a known factor"
// so that the unsigned-short range is used fully).
//
// Encoding, per volume and per timestep (linear, zero-preserving):
//   s = max / 65535            (max = largest value of the volume, s = 0 for an empty volume)
//   q = round(v / s)           clamped to [0, 65535]; v <= 0 (and v = 0 exactly) -> q = 0
//   v' = q * s                 decoding, also what a GL_R16 texture times `max` gives
// Error bound: for 0 <= v <= max the rounding error is at most s/2 = max / 131070 in exact
// arithmetic; evaluating v/s and q*s in double and storing v' as float adds at most one float
// rounding of v' (relative 2^-24), so
//   |v - v'| <= max / 131070 + max * 2^-24         (kQuantisationErrorBound below).
// Zero stays exactly zero (empty-space skipping in the renderer relies on it).
// For the renderer this is an optical-depth error of at most dz * max / 131070 per layer, e.g.
// 250 m * 0.05 /m / 131070 ≈ 1e-4: far below what is visible.
#include <cstdint>
#include <span>

namespace nph::cache {

inline constexpr double kQuantisationLevels = 65535.0;

/// Documented worst-case absolute decoding error for a volume whose maximum is `max_value`.
inline double quantisationErrorBound(double max_value) {
  return max_value / (2.0 * kQuantisationLevels) + max_value * 0x1p-24;
}

/// Encodes `values` (non-negative, max = `max_value`) into `out` (same length).
void quantise(std::span<const float> values, float max_value, std::span<std::uint16_t> out);
/// Decodes `codes` with the scale of `max_value` into `out` (same length).
void dequantise(std::span<const std::uint16_t> codes, float max_value, std::span<float> out);

}  // namespace nph::cache
