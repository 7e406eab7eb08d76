#pragma once
// Checksums of .nph file blocks: XXH64 (seed 0) from the xxHash library (Collet; the hash zstd
// itself uses for frame checksums). 64 bits make an undetected random corruption of a chunk
// practically impossible (2^-64), and XXH64 runs at memory bandwidth.
#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace nph::cache {

std::uint64_t xxh64(std::span<const std::byte> bytes);

/// XXH64 (seed 0) of bytes fed in pieces: digest() equals xxh64() of their concatenation. For a
/// chunk read and decoded as a stream (NphReader::readSlices) that is never held whole.
class Xxh64Stream {
 public:
  Xxh64Stream();
  ~Xxh64Stream();
  Xxh64Stream(const Xxh64Stream&) = delete;
  Xxh64Stream& operator=(const Xxh64Stream&) = delete;
  void reset();
  void update(std::span<const std::byte> bytes);
  std::uint64_t digest() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};
/// 16 lower-case hex digits, as stored in the index.
std::string toHex(std::uint64_t value);

}  // namespace nph::cache
