#include "vwg/hash.hpp"

#include <cstring>

namespace vwg {

std::uint64_t hash_bytes(const void* data, std::size_t n, std::uint64_t seed) {
  // Word-at-a-time multiply-rotate, finished by mix64. Reads little-endian words with memcpy so
  // the result does not depend on alignment.
  const auto* p = static_cast<const unsigned char*>(data);
  std::uint64_t h = mix64(seed ^ (n * 0x9E3779B97F4A7C15ULL));
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    std::uint64_t w;
    std::memcpy(&w, p + i, 8);
    h ^= w * 0x9E3779B97F4A7C15ULL;
    h = ((h << 27) | (h >> 37)) * 0x94D049BB133111EBULL;
  }
  std::uint64_t tail = 0;
  for (std::size_t k = 0; i + k < n; ++k) tail |= static_cast<std::uint64_t>(p[i + k]) << (8 * k);
  h ^= tail * 0xBF58476D1CE4E5B9ULL;
  return mix64(h);
}

}  // namespace vwg
