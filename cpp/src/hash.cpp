#include "vwg/hash.hpp"

// xxHash's XXH3 (libxxhash-dev), compiled in here from its header alone, so nothing links to it:
// a stable, platform-independent hash that reads several words at once (9.3 GB/s on 480 KB maps,
// where the word-at-a-time multiply-rotate chain it replaced made 4.4). A crowd's recorder names
// every changed map by its hash each frame (100 robots: 48 MB).
#define XXH_INLINE_ALL
#include <xxhash.h>

static_assert(XXH_VERSION_NUMBER >= 800, "XXH3's values are stable from xxHash 0.8.0 on");

namespace vwg {

std::uint64_t hash_bytes(const void* data, std::size_t n, std::uint64_t seed) {
  return XXH3_64bits_withSeed(data, n, seed);
}

}  // namespace vwg
