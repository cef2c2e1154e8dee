#include "vwg/hash.hpp"

// xxHash's XXH3 (libxxhash-dev), compiled in here from its header alone, so nothing links to it:
// a stable, platform-independent hash that reads several words at once. The word-at-a-time
// multiply-rotate chain it replaced hashed 2.6 GB/s, and a crowd's recorder names every changed
// map by its hash each frame (100 robots: 48 MB).
#define XXH_INLINE_ALL
#include <xxhash.h>

namespace vwg {

std::uint64_t hash_bytes(const void* data, std::size_t n, std::uint64_t seed) {
  return XXH3_64bits_withSeed(data, n, seed);
}

}  // namespace vwg
