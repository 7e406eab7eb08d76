#pragma once
// Internal: the on-disk header of .nph version 1 (layout documented in nph_cache.h) and the
// little-endian encode/decode helpers shared by NphWriter and NphReader.
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace nph::cache::detail {

static_assert(std::endian::native == std::endian::little,
              ".nph files are little-endian; a big-endian port must byte-swap here");

inline constexpr std::array<char, 8> kMagic = {'N', 'P', 'H', 'C', 'A', 'C', 'H', 'E'};

struct Header {
  std::uint32_t version = 0;
  std::uint32_t header_bytes = 0;
  std::uint64_t index_offset = 0;
  std::uint64_t index_bytes = 0;
  std::uint64_t index_xxh64 = 0;
  std::uint64_t file_bytes = 0;
};

inline constexpr std::size_t kHeaderChecksumOffset = 56;

template <class T>
void put(std::byte* at, T value) {
  std::memcpy(at, &value, sizeof(T));
}
template <class T>
T get(const std::byte* at) {
  T value;
  std::memcpy(&value, at, sizeof(T));
  return value;
}

}  // namespace nph::cache::detail
