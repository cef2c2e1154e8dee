// Jump Point Search (Harabor & Grastien 2011) on an 8-connected grid without corner cutting: the
// shortest paths of A* (the same lengths), found by expanding only the cells where a shortest path
// may turn. Straight runs through open space are scanned, not queued, so on open maps it expands a
// small fraction of A*'s cells.
#pragma once

#include <cstdint>
#include <vector>

#include "vwg/plan/grid_graph.hpp"

namespace vwg::plan {

/// A reusable Jump Point Search; like AStar it keeps its work arrays between searches and is not
/// thread-safe (one object per thread). Moves: 8-connected, a diagonal only past two free sides
/// (GridSearchOptions{diagonal=true, corner_cutting=false}); the heuristic is the options'.
class JumpPointSearch {
 public:
  /// The shortest path from `start` to `goal` as every cell it passes (as AStar returns it), or no
  /// path. Throws SchemaError for a cell outside the grid, a blocked start, options other than
  /// 8-connected without corner cutting, or a heuristic that overestimates.
  GridPath search(const BlockedGrid& grid, Cell start, Cell goal, const GridSearchOptions& options = {});

  /// Jump points expanded by the last search.
  std::size_t expanded() const { return expanded_; }

 private:
  /// The next jump point from `from` stepping by (dc, dr), or -1: a cell where a shortest path
  /// may turn (a forced neighbour), the goal, or a diagonal step from which a straight jump finds one.
  std::int32_t jump(std::int32_t from, int dc, int dr) const;
  std::int32_t jump_straight(std::int32_t from, std::int32_t step, int dc) const;
  void relax(std::int32_t from, std::int32_t to);
  /// The step (-1, 0 or 1 in columns and rows) from padded index `from` towards `to`.
  void direction(std::int32_t from, std::int32_t to, int& dc, int& dr) const;
  bool free(std::int32_t i) const { return blocked_[i] == 0; }

  struct Entry {
    double f;
    std::int32_t node;
    bool operator<(const Entry& o) const { return f > o.f; }  // a min-heap through std::push_heap
  };

  // The search in progress.
  const std::uint8_t* blocked_ = nullptr;
  std::int32_t stride_ = 0, goal_ = -1, goal_row_ = 0, goal_col_ = 0;
  Heuristic heuristic_ = Heuristic::Euclidean;
  std::vector<double> g_;
  std::vector<std::int32_t> parent_;
  std::vector<std::uint32_t> marks_;  ///< stamp_: open, stamp_ + 1: closed
  std::uint32_t stamp_ = 0;
  std::vector<Entry> open_;
  std::size_t expanded_ = 0;
};

}  // namespace vwg::plan
