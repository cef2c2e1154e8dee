// A* on a grid (Hart, Nilsson & Raphael 1968): the shortest path between two cells of a BlockedGrid
// with the moves and costs of GridSearchOptions. The decision algorithm of the paper's case study.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "vwg/plan/grid_graph.hpp"

namespace vwg::plan {

/// A reusable A* search. It keeps its work arrays between searches, so planning many times on
/// grids of one size allocates nothing after the first searches (and never clears whole arrays:
/// every search stamps the cells it touches). Not thread-safe: one object per thread.
/// Among paths of equal length, which one is returned is unspecified.
class AStar {
 public:
  /// The shortest path from `start` to `goal`, or no path (empty, infinite length).
  /// Throws SchemaError("start"/"goal") for a cell outside the grid and for a blocked start, and
  /// SchemaError("heuristic") for options that would not give shortest paths. A blocked goal has no path.
  GridPath search(const BlockedGrid& grid, Cell start, Cell goal, const GridSearchOptions& options = {});

  /// Cells expanded (taken off the open list) by the last search.
  std::size_t expanded() const { return expanded_; }

 private:
  /// What a search knows of a cell it reached. The open/closed marks live apart, in a small array
  /// that stays in cache: most neighbours looked at are already closed, and are then not read here.
  struct Node {
    double g;             ///< cost from the start
    std::int32_t parent;  ///< padded index of the previous cell on the best path found
  };

  /// An open-list entry: f as the bits of a non-negative double (which order like the doubles).
  /// Entries made stale by a shorter path to their cell are skipped when popped (lazy deletion).
  struct Entry {
    std::uint64_t key;
    std::int32_t node;
  };

  // The open list is a radix heap (Ahuja, Mehlhorn, Orlin & Tarjan 1990): with a consistent
  // heuristic the keys A* pops never decrease, and for such monotone keys a radix heap pops in the
  // same order as a binary heap, faster: searches on the MovingAI 512×512 maps took about half
  // the time of a 4-ary heap with decrease-key. Its digits are 6 bits wide, not 1: bucket 0 holds
  // keys equal to the last popped key, bucket 1 + 64 L + d those whose highest 6-bit digit that
  // differs from it is digit L, where theirs is d. Buckets in index order hold ever larger keys,
  // and an entry moves down a whole digit at a time: on 512 × 512 city and maze maps a third of
  // the moves of one bucket per bit, and 27 % fewer instructions per expansion on city blocks,
  // 9 % on a maze (callgrind, with the changes below).
  static constexpr int kDigitBits = 6, kDigits = 1 << kDigitBits, kLevels = (64 + kDigitBits - 1) / kDigitBits;
  static constexpr int kBuckets = 1 + kLevels * kDigits;

  /// A bucket's entries: a plain growable array, emptied by setting its size. With std::vector
  /// (push_back, clear) a search took 567 instructions an expansion on a city map instead of
  /// 472, and 383 instead of 325 on a maze (callgrind).
  struct Bucket {
    std::unique_ptr<Entry[]> data;
    std::uint32_t size = 0, capacity = 0;
    void push(const Entry& e) {
      if (size == capacity) [[unlikely]] grow();
      data[size++] = e;
    }
    void grow();
  };

  void push(double f, std::int32_t node);
  void place(const Entry& e);  ///< into its bucket, marked occupied (push, and pop's spreading)
  std::int32_t pop();
  int bucket_of(std::uint64_t key) const;

  void prepare(std::size_t padded_size);

  /// The search with its moves and heuristic as constants (search() picks one of these): whether it
  /// reached `target`, its path then in nodes_' parents.
  template <bool Diagonal, bool CornerCutting, Heuristic H>
  bool run(const BlockedGrid& grid, std::int32_t source, std::int32_t target, Cell goal);

  std::vector<Node> nodes_;
  std::vector<std::uint16_t> marks_;  ///< stamp_: open, stamp_ + 1: closed, anything else: untouched
  std::array<Bucket, kBuckets> buckets_;
  /// Bit b set when bucket b may hold entries (bucket 0's bit is not looked at): finds the first in a few words.
  std::array<std::uint64_t, (kBuckets + 63) / 64> occupied_{};
  std::uint64_t last_key_ = 0;
  std::size_t open_size_ = 0;
  std::uint16_t stamp_ = 0;
  std::size_t expanded_ = 0;
};

/// A one-off search (a fresh AStar).
GridPath astar(const BlockedGrid& grid, Cell start, Cell goal, const GridSearchOptions& options = {});

}  // namespace vwg::plan
