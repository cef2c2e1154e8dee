// Stable, platform-independent 64-bit hashing used for blob names and determinism checks
// (hash_bytes is xxHash's XXH3).
#pragma once

#include <cstddef>
#include <cstdint>

namespace vwg {

/// Final mixing step of SplitMix64: a bijection that spreads every input bit over the output.
constexpr std::uint64_t mix64(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xBF58476D1CE4E5B9ULL;
  x ^= x >> 27;
  x *= 0x94D049BB133111EBULL;
  x ^= x >> 31;
  return x;
}

/// Hash of `n` bytes, continuing from `seed` (so several pieces can be chained).
std::uint64_t hash_bytes(const void* data, std::size_t n, std::uint64_t seed = 0);

/// Combine a running hash with one more 64-bit word.
constexpr std::uint64_t hash_combine(std::uint64_t h, std::uint64_t word) {
  return mix64(h ^ (word + 0x9E3779B97F4A7C15ULL + (h << 6) + (h >> 2)));
}

}  // namespace vwg
