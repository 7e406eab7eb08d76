#include "cache/checksum.h"

#include <xxhash.h>

#include <fmt/format.h>

namespace nph::cache {

std::uint64_t xxh64(std::span<const std::byte> bytes) { return XXH64(bytes.data(), bytes.size(), 0); }

std::string toHex(std::uint64_t value) { return fmt::format("{:016x}", value); }

}  // namespace nph::cache
