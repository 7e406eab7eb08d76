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
#include <cstddef>
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

// Horizontal wind (U, V; issue 13 follow-up: the motion blend of docs/animation.md on the .nph
// route). A fixed step instead of a per-volume scale, signed:
//   q = round(u / 0.01 m/s)    clamped to [-32767, 32767], i.e. |u| <= 327.67 m/s (jet streams
//                              peak near 100 m/s); a non-finite u (a broken file) -> 0, calm,
//                              as volume/detail.h buildDetailWind reads it
//   u' = q * 0.01 m/s          decoding
// Error bound for |u| <= 327.67 m/s: 0.005 m/s from rounding, plus one float rounding of u'
// (relative 2^-24: < 2e-5 m/s). Over an hour between timesteps that moves a trajectory of
// engine::blendVolumes by at most 18 m, against model columns of 1-10 km.
inline constexpr double kWindStep_m_per_s = 0.01;
inline constexpr double kWindMaxCode = 32767.0;
inline constexpr double kWindErrorBound_m_per_s = 0.5 * kWindStep_m_per_s + kWindMaxCode * kWindStep_m_per_s * 0x1p-24;

/// Encodes `values` [m/s] into `out` (same length); returns how many were non-finite (stored as 0).
std::size_t quantiseWind(std::span<const float> values, std::span<std::int16_t> out);
/// Decodes `codes` into `out` [m/s] (same length).
void dequantiseWind(std::span<const std::int16_t> codes, std::span<float> out);

// The wind chunk's bytes (before zstd): the codes in rows of `row` (nx) values, each code replaced
// by its difference from the one before it in the row (0 before the first), modulo 2^16, zigzag
// coded (0, -1, 1, -2, ... -> 0, 1, 2, 3, ...), then all high bytes followed by all low bytes. A
// bijection; a wind smooth along x leaves mostly small numbers and a high-byte plane of near-zeros,
// which zstd packs to about half the plain codes' size (the coarse storm: 407 kB -> 202 kB a
// timestep; docs/conversion.md).
/// Packs `codes` into `out` (2 bytes per code).
void packWindCodes(std::span<const std::int16_t> codes, std::size_t row, std::span<std::byte> out);
/// Inverts packWindCodes.
void unpackWindCodes(std::span<const std::byte> packed, std::size_t row, std::span<std::int16_t> codes);

}  // namespace nph::cache
