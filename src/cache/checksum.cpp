#include "cache/checksum.h"

#include <xxhash.h>

#include <fmt/format.h>

namespace nph::cache {

std::uint64_t xxh64(std::span<const std::byte> bytes) { return XXH64(bytes.data(), bytes.size(), 0); }

struct Xxh64Stream::State {
  XXH64_state_t xxh;
};
Xxh64Stream::Xxh64Stream() : state_(std::make_unique<State>()) { reset(); }
Xxh64Stream::~Xxh64Stream() = default;
void Xxh64Stream::reset() { XXH64_reset(&state_->xxh, 0); }
void Xxh64Stream::update(std::span<const std::byte> bytes) { XXH64_update(&state_->xxh, bytes.data(), bytes.size()); }
std::uint64_t Xxh64Stream::digest() const { return XXH64_digest(&state_->xxh); }

std::string toHex(std::uint64_t value) { return fmt::format("{:016x}", value); }

}  // namespace nph::cache
