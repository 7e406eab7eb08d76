#pragma once
// Checksums of .nph file blocks: XXH64 (seed 0) from the xxHash library (Collet; the hash zstd
// itself uses for frame checksums). 64 bits make an undetected random corruption of a chunk
// practically impossible (2^-64), and XXH64 runs at memory bandwidth.
#include <cstdint>
#include <span>
#include <string>

namespace nph::cache {

std::uint64_t xxh64(std::span<const std::byte> bytes);
/// 16 lower-case hex digits, as stored in the index.
std::string toHex(std::uint64_t value);

}  // namespace nph::cache
