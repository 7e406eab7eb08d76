#pragma once
// Internal: the JSON index of a .nph file (see nph_cache.h) and its encoding/decoding.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cache/nph_cache.h"

namespace nph::cache {

/// Where a compressed block lies in the file.
struct ChunkRef {
  std::uint64_t offset = 0;
  std::uint64_t bytes = 0;      ///< compressed
  std::uint64_t raw_bytes = 0;  ///< decompressed
  std::uint64_t xxh64 = 0;      ///< of the compressed bytes
  bool present() const { return bytes > 0; }
};

nlohmann::json encodeIndex(const NphMetadata& metadata, const std::vector<TimestepInfo>& timesteps,
                           const ChunkRef& geolocation, const ChunkRef& terrain = {});

struct DecodedIndex {
  NphMetadata metadata;
  std::vector<TimestepInfo> timesteps;
  ChunkRef geolocation;
  ChunkRef terrain;  ///< absent in files before issue 14
  int nz = 0;
};
/// Throws InputError naming `file` when a field is missing or has the wrong type.
DecodedIndex decodeIndex(const std::string& file, const std::string& text);

}  // namespace nph::cache
