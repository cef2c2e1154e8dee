// Numbers that no two calls ever share in a process (a blob's content revision, an event list's
// serial), used to tell contents apart: equal numbers mean the same content. Each thread takes
// them a block at a time from one counter, since one counter bumped on every write would bounce
// between the cores when robots' maps are written on several threads at once. The numbers are
// only compared for equality, so their order across threads does not matter.
// Private to vwg's libraries (beside their sources, under cpp/): not installed.
#pragma once

#include <atomic>
#include <cstdint>

namespace vwg {

/// The next number of the sequence named by `Tag` (never 0).
template <class Tag>
std::uint64_t next_unique_number() {
  constexpr std::uint64_t kBlock = 1024;
  static std::atomic<std::uint64_t> next_block{1};
  thread_local std::uint64_t next = 0, end = 0;
  if (next == end) {
    next = next_block.fetch_add(kBlock, std::memory_order_relaxed);
    end = next + kBlock;
  }
  return next++;
}

}  // namespace vwg
