#include "vwg/plan/astar.hpp"

#include <algorithm>
#include <bit>
#include <limits>

namespace vwg::plan {

int AStar::bucket_of(std::uint64_t key) const {
  return key == last_key_ ? 0 : 64 - std::countl_zero(key ^ last_key_);
}

void AStar::push(double f, std::int32_t node) {
  std::uint64_t key = std::bit_cast<std::uint64_t>(f);
  // Consistency makes f non-decreasing along a search, but rounding can put a child's f one ulp
  // below its parent's; such a key is treated as equal to the last popped one.
  key = std::max(key, last_key_);
  const int b = bucket_of(key);
  buckets_[b].push_back({key, node});
  if (b > 0) occupied_ |= std::uint64_t{1} << (b - 1);
  ++open_size_;
}

std::int32_t AStar::pop() {
  if (buckets_[0].empty()) {
    // Refill bucket 0: the smallest key of the first non-empty bucket becomes the reference, and
    // that bucket's entries spread into lower buckets (each entry moves down at most 64 times).
    const int i = 1 + std::countr_zero(occupied_);
    std::vector<Entry>& from = buckets_[i];
    occupied_ &= ~(std::uint64_t{1} << (i - 1));
    std::uint64_t smallest = from.front().key;
    for (const Entry& e : from) smallest = std::min(smallest, e.key);
    last_key_ = smallest;
    for (const Entry& e : from) {
      const int b = bucket_of(e.key);
      buckets_[b].push_back(e);
      if (b > 0) occupied_ |= std::uint64_t{1} << (b - 1);
    }
    from.clear();
  }
  // Among equal keys the last pushed: usually the deepest cell, which reaches the goal sooner.
  const std::int32_t node = buckets_[0].back().node;
  buckets_[0].pop_back();
  --open_size_;
  return node;
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
  for (auto& bucket : buckets_) bucket.clear();
  occupied_ = 0;
  last_key_ = 0;
  open_size_ = 0;
  expanded_ = 0;
}

GridPath AStar::search(const BlockedGrid& grid, Cell start, Cell goal, const GridSearchOptions& options) {
  validate(options);
  check_cell(grid, start, "start", true);
  check_cell(grid, goal, "goal", false);
  GridPath result;
  if (grid.blocked(goal)) return result;

  prepare(grid.padded().size());
  const std::uint16_t open = stamp_, closed = static_cast<std::uint16_t>(stamp_ + 1);
  const std::int32_t source = grid.index(start), target = grid.index(goal);
  const std::int32_t stride = grid.stride();
  const Heuristic heuristic = options.heuristic;
  auto estimate = [&](std::int32_t node) {
    return heuristic_distance(heuristic, node / stride - (goal.row + 1), node % stride - (goal.col + 1));
  };

  nodes_[source] = Node{0.0, -1};
  marks_[source] = open;
  push(estimate(source), source);

  std::array<Step, 8> steps;
  bool found = false;
  while (open_size_ > 0) {
    const std::int32_t u = pop();
    if (marks_[u] == closed) continue;  // a stale entry: u was closed through a shorter path
    marks_[u] = closed;
    ++expanded_;
    if (u == target) {
      found = true;
      break;
    }
    const double gu = nodes_[u].g;
    const int count = moves_from(grid, u, options, steps);
    for (int k = 0; k < count; ++k) {
      const std::int32_t v = steps[k].to;
      const double gv = gu + steps[k].cost;
      std::uint16_t& mark = marks_[v];
      if (mark == closed) continue;  // consistent heuristics never reopen a closed cell
      Node& nv = nodes_[v];
      if (mark == open && gv >= nv.g) continue;
      mark = open;
      nv.g = gv;
      nv.parent = u;
      // h is recomputed rather than stored: a smaller node keeps more of the map in cache.
      push(gv + estimate(v), v);
    }
  }
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
