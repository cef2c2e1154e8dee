#include "vwg/plan/astar.hpp"

#include <algorithm>
#include <bit>
#include <limits>

namespace vwg::plan {

// push, pop, place and bucket_of are inlined into the search loop: as calls, their entry and exit
// took a tenth of the instructions of an expansion.
[[gnu::always_inline]] inline int AStar::bucket_of(std::uint64_t key) const {
  const std::uint64_t differ = key ^ last_key_;
  if (differ == 0) return 0;
  const int level = (63 - std::countl_zero(differ)) / kDigitBits;
  return 1 + level * kDigits + static_cast<int>((key >> (level * kDigitBits)) & (kDigits - 1));
}

void AStar::Bucket::grow() {
  const std::uint32_t bigger = std::max<std::uint32_t>(16, 2 * capacity);
  std::unique_ptr<Entry[]> more(new Entry[bigger]);
  std::copy(data.get(), data.get() + size, more.get());
  data = std::move(more);
  capacity = bigger;
}

[[gnu::always_inline]] inline void AStar::place(const Entry& e) {
  const int b = bucket_of(e.key);
  buckets_[b].push(e);
  occupied_[b >> 6] |= std::uint64_t{1} << (b & 63);
}

[[gnu::always_inline]] inline void AStar::push(double f, std::int32_t node) {
  // Consistency makes f non-decreasing along a search, but rounding can put a child's f one ulp
  // below its parent's; such a key is treated as equal to the last popped one.
  place({std::max(std::bit_cast<std::uint64_t>(f), last_key_), node});
  ++open_size_;
}

[[gnu::always_inline]] inline std::int32_t AStar::pop() {
  --open_size_;
  // Among equal keys the last pushed: usually the deepest cell, which reaches the goal sooner.
  Bucket& equal = buckets_[0];
  if (equal.size > 0) return equal.data[--equal.size].node;
  // Refill: the smallest key of the first non-empty bucket becomes the reference, and that
  // bucket's entries spread into lower buckets (each entry moves down at most kLevels times).
  occupied_[0] &= ~std::uint64_t{1};
  int word = 0;
  while (occupied_[word] == 0) ++word;
  const int i = word * 64 + std::countr_zero(occupied_[word]);
  occupied_[word] &= occupied_[word] - 1;
  Bucket& from = buckets_[i];
  const Entry* begin = from.data.get();
  const Entry* end = begin + from.size;
  from.size = 0;
  if (end - begin == 1) {  // the usual case: the next key alone in its bucket
    last_key_ = begin->key;
    return begin->node;
  }
  std::uint64_t smallest = begin->key;
  for (const Entry* e = begin + 1; e != end; ++e) smallest = std::min(smallest, e->key);
  last_key_ = smallest;
  for (const Entry* e = begin; e != end; ++e) place(*e);
  return equal.data[--equal.size].node;
}

void AStar::prepare(std::size_t padded_size) {
  if (nodes_.size() != padded_size) {
    nodes_.assign(padded_size, Node{0.0, -1});
    marks_.assign(padded_size, 0);
    stamp_ = 0;
  }
  // Two stamp values per search; on wrap-around, clear the marks once so old stamps cannot match.
  if (stamp_ >= std::numeric_limits<std::uint16_t>::max() - 2) {
    std::fill(marks_.begin(), marks_.end(), std::uint16_t{0});
    stamp_ = 0;
  }
  stamp_ += 2;
  for (Bucket& bucket : buckets_) bucket.size = 0;
  occupied_.fill(0);
  last_key_ = 0;
  open_size_ = 0;
  expanded_ = 0;
}

// The search for one set of moves and one heuristic, each a constant here: the compiler drops the
// branches on them, and the heuristic of a neighbour comes from the expanded cell's offset to the goal
// (one division per expansion, not one per neighbour).
template <bool Diagonal, bool CornerCutting, Heuristic H>
bool AStar::run(const BlockedGrid& grid, std::int32_t source, std::int32_t target, Cell goal) {
  const std::uint8_t* blocked = grid.padded().data();
  const std::int32_t s = grid.stride();
  const int goal_row = goal.row + 1, goal_col = goal.col + 1;  // padded
  const std::uint16_t open = stamp_, closed = static_cast<std::uint16_t>(stamp_ + 1);

  // v, reached from u at cost gv, is drow rows and dcol columns from the goal.
  auto relax = [&](std::int32_t v, std::int32_t u, double gv, int drow, int dcol) {
    std::uint16_t& mark = marks_[v];
    if (mark == closed) return;  // consistent heuristics never reopen a closed cell
    Node& nv = nodes_[v];
    if (mark == open && gv >= nv.g) return;
    mark = open;
    nv.g = gv;
    nv.parent = u;
    // h is recomputed rather than stored: a smaller node keeps more of the map in cache.
    push(gv + heuristic_distance(H, drow, dcol), v);
  };

  nodes_[source] = Node{0.0, -1};
  marks_[source] = open;
  push(heuristic_distance(H, source / s - goal_row, source % s - goal_col), source);
  while (open_size_ > 0) {
    const std::int32_t u = pop();
    if (marks_[u] == closed) continue;  // a stale entry: u was closed through a shorter path
    marks_[u] = closed;
    ++expanded_;
    if (u == target) return true;
    const double gu = nodes_[u].g;
    const int row = u / s, drow = row - goal_row, dcol = u - row * s - goal_col;
    // The moves of moves_from(), in its order.
    if (!blocked[u + 1]) relax(u + 1, u, gu + 1.0, drow, dcol + 1);
    if (!blocked[u - 1]) relax(u - 1, u, gu + 1.0, drow, dcol - 1);
    if (!blocked[u + s]) relax(u + s, u, gu + 1.0, drow + 1, dcol);
    if (!blocked[u - s]) relax(u - s, u, gu + 1.0, drow - 1, dcol);
    if constexpr (Diagonal) {
      auto diagonal = [&](std::int32_t dr, std::int32_t dc, int rows, int cols) {
        const std::int32_t v = u + dr + dc;
        if (blocked[v]) return;
        if (!CornerCutting && (blocked[u + dr] || blocked[u + dc])) return;
        relax(v, u, gu + kDiagonalCost, drow + rows, dcol + cols);
      };
      diagonal(s, 1, 1, 1);
      diagonal(s, -1, 1, -1);
      diagonal(-s, 1, -1, 1);
      diagonal(-s, -1, -1, -1);
    }
  }
  return false;
}

GridPath AStar::search(const BlockedGrid& grid, Cell start, Cell goal, const GridSearchOptions& options) {
  validate(options);
  check_cell(grid, start, "start", true);
  check_cell(grid, goal, "goal", false);
  GridPath result;
  if (grid.blocked(goal)) return result;

  prepare(grid.padded().size());
  const std::int32_t source = grid.index(start), target = grid.index(goal);
  auto with = [&]<bool Diagonal, bool CornerCutting>() {
    switch (options.heuristic) {
      case Heuristic::Euclidean: return run<Diagonal, CornerCutting, Heuristic::Euclidean>(grid, source, target, goal);
      case Heuristic::Octile: return run<Diagonal, CornerCutting, Heuristic::Octile>(grid, source, target, goal);
      case Heuristic::Manhattan: return run<Diagonal, CornerCutting, Heuristic::Manhattan>(grid, source, target, goal);
      case Heuristic::Zero: break;
    }
    return run<Diagonal, CornerCutting, Heuristic::Zero>(grid, source, target, goal);
  };
  const bool found = !options.diagonal              ? with.template operator()<false, false>()
                     : options.corner_cutting ? with.template operator()<true, true>()
                                              : with.template operator()<true, false>();
  if (!found) return result;

  for (std::int32_t n = target; n != -1; n = nodes_[n].parent) result.cells.push_back(grid.cell(n));
  std::reverse(result.cells.begin(), result.cells.end());
  result.length = nodes_[target].g;
  return result;
}

GridPath astar(const BlockedGrid& grid, Cell start, Cell goal, const GridSearchOptions& options) {
  AStar search;
  return search.search(grid, start, goal, options);
}

}  // namespace vwg::plan
