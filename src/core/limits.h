#pragma once
// Resource limits: the one place that declares how much a file, a scene or an environment value
// may make nephele allocate or loop (issue #18, docs/reliability.md holds the same table).
//
// Rule: nothing derived from a file is trusted. Sizes are multiplied with overflow checks
// (checkedProduct), and every float -> integer conversion is range-checked before the cast
// (toIntChecked: a cast of 1e20 or NaN to int is undefined behaviour, [conv.fpint]). Each limit
// is checked before allocating, and the error names the file, the field, the limit and how to
// raise it.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>

namespace nph::limits {

/// Voxels (or cells) of one 3-D grid a file may declare: 2^31, i.e. 8 GiB per float field, far
/// above the largest real domains (a 2000 x 2000 x 100 WRF domain is 4e8) and below the point
/// where int indices overflow.
inline constexpr std::uint64_t kMaxGridPoints = std::uint64_t(1) << 31;
/// Vertical levels of a derived (resampled) grid. 4096 levels of 25 m span 100 km, the whole
/// atmosphere nephele renders at a finer step than any model output.
inline constexpr int kMaxDerivedLevels = 4096;
/// Pixels of one image (output, basemap): 8192 x 8192. A 16384^2 RGBA32F target needs 4 GiB of
/// GL memory plus the DLM and failed with GL_OUT_OF_MEMORY after 565 s on llvmpipe.
inline constexpr std::uint64_t kMaxImagePixels = std::uint64_t(8192) * 8192;
/// Pixels of a basemap image held in memory (the globe's whole-Earth image): 8192 x 4096 (400 MB as
/// float RGB).
inline constexpr std::uint64_t kMaxBasemapPixels = std::uint64_t(8192) * 4096;
/// Pixels of a basemap source raster (scene/basemap.h): 65536 x 65536. GDAL's warper reads only the
/// windows it needs, in chunks, so the source may be far larger than what is held in memory; past
/// this a header (a 373 KB PNG declaring 16000 x 8000 once took 3.3 GB) is taken as hostile.
inline constexpr std::uint64_t kMaxBasemapSourcePixels = std::uint64_t(65536) * 65536;
/// Frames one animation may plan: 10 hours at 60 frames/s.
inline constexpr std::int64_t kMaxFrames = std::int64_t(60) * 3600 * 10;
/// Nesting depth of JSON in scene files, keyframe files and .nph indices. nlohmann::json's dump()
/// and destructor recurse per level; 100 000 levels overflowed the stack. Real files use < 10.
inline constexpr int kMaxJsonDepth = 64;
/// Default memory budget of one load (NEPHELE_IO_MEMORY_BUDGET_MB overrides it).
inline constexpr std::uint64_t kDefaultMemoryBudgetBytes = std::uint64_t(8) << 30;
/// Largest NEPHELE_IO_MEMORY_BUDGET_MB accepted: 2^24 MiB = 16 TiB (so MiB -> bytes cannot wrap).
inline constexpr std::uint64_t kMaxMemoryBudgetMiB = std::uint64_t(1) << 24;

/// The product of `factors`, or nullopt when it overflows 64 bits.
std::optional<std::uint64_t> checkedProduct(std::initializer_list<std::uint64_t> factors);

/// The product of `factors` (e.g. nx, ny, nz); throws InputError
/// "<file>: <field> = <a> x <b> x ... exceeds the limit of <limit> (<how to raise>)" when it
/// overflows or exceeds `limit`.
std::uint64_t requireProductWithin(const std::string& file, const std::string& field,
                                   std::initializer_list<std::uint64_t> factors, std::uint64_t limit,
                                   const std::string& how_to_raise);

/// `v` as an Int when it is finite and within Int's range, else nullopt (no UB on the cast).
template <class Int>
std::optional<Int> toIntChecked(double v) {
  // Int's range as [lo, hi) with exactly representable bounds: [-2^(N-1), 2^(N-1)) for signed,
  // [0, 2^N) for unsigned N-bit integers (NaN fails both comparisons).
  constexpr double hi = 2.0 * double(std::numeric_limits<Int>::max() / 2 + 1);
  constexpr double lo = std::numeric_limits<Int>::is_signed ? -hi : 0.0;
  if (!(v >= lo && v < hi)) return std::nullopt;
  return static_cast<Int>(v);
}

/// NEPHELE_IO_MEMORY_BUDGET_MB parsed strictly: unset -> kDefaultMemoryBudgetBytes; a whole
/// number of MiB in [1, kMaxMemoryBudgetMiB] -> bytes; anything else (garbage, 0, negative,
/// "12abc", too large) -> UsageError naming the variable and the accepted range.
std::uint64_t memoryBudgetBytesFromEnv();

/// NEPHELE_HDF5_OPEN_TIMEOUT_S parsed strictly: unset -> 300; a whole number of seconds in
/// [1, 86400] -> it; anything else -> UsageError naming the variable and the range. How long a
/// netCDF-4 file's metadata may take to parse (io/netcdf_reader.cpp probeHdf5OpenInChild).
std::uint64_t hdf5OpenTimeoutSecondsFromEnv();

/// Parses `text` as an unsigned integer in [lo, hi] (decimal digits only, nothing else);
/// UsageError "<what> = "<text>": expected a whole number in [lo, hi]" otherwise.
std::uint64_t parseUnsignedStrict(const std::string& what, const std::string& text, std::uint64_t lo, std::uint64_t hi);

}  // namespace nph::limits
