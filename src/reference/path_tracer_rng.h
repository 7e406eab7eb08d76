#pragma once
// Random numbers for the path tracer: one independent stream per pixel, so an image does not
// depend on how TBB schedules pixels onto threads (bit-identical for any thread count).
// Stream seed = SplitMix64(seed ⊕ SplitMix64(pixel index)); generator = xoshiro256++
// (Blackman & Vigna 2021, "Scrambled linear pseudorandom number generators"), state filled by
// SplitMix64 as its authors recommend.
#include <cstdint>

namespace nph::reference {

inline std::uint64_t splitMix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

class PathRng {
 public:
  PathRng(std::uint64_t seed, std::uint64_t stream) {
    std::uint64_t h = stream;
    std::uint64_t sm = seed ^ splitMix64(h);
    for (auto& w : s_) w = splitMix64(sm);
  }
  std::uint64_t nextU64() {
    const std::uint64_t result = rotl(s_[0] + s_[3], 23) + s_[0];
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return double(nextU64() >> 11) * 0x1.0p-53; }
  double operator()() { return uniform(); }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4]{};
};

}  // namespace nph::reference
