#include "vwg/plan/jps.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "vwg/error.hpp"

namespace vwg::plan {

std::int32_t JumpPointSearch::jump_straight(std::int32_t at, std::int32_t step, int dc) const {
  // Along a row (dc != 0) a cell is a jump point when the cell beside it is free and the one
  // beside the previous cell is blocked: a path can turn there that no diagonal reached earlier
  // (no corner cutting). The same across rows.
  const std::int32_t side = dc != 0 ? stride_ : 1;
  for (; free(at); at += step) {
    if (at == goal_) return at;
    if ((free(at - side) && !free(at - step - side)) || (free(at + side) && !free(at - step + side))) return at;
  }
  return -1;
}

std::int32_t JumpPointSearch::jump(std::int32_t at, int dc, int dr) const {
  const std::int32_t a = dc, b = dr * stride_;
  if (dc == 0 || dr == 0) return jump_straight(at, a + b, dc);
  for (;;) {
    if (!free(at)) return -1;
    if (at == goal_) return at;
    // A diagonal step is a jump point when either straight run from it finds one.
    if (jump_straight(at + a, a, dc) >= 0 || jump_straight(at + b, b, 0) >= 0) return at;
    // The next diagonal step passes two free sides.
    if (!free(at + a) || !free(at + b)) return -1;
    at += a + b;
  }
}

void JumpPointSearch::direction(std::int32_t from, std::int32_t to, int& dc, int& dr) const {
  dr = (to / stride_ > from / stride_) - (to / stride_ < from / stride_);
  dc = (to % stride_ > from % stride_) - (to % stride_ < from % stride_);
}

void JumpPointSearch::relax(std::int32_t from, std::int32_t to) {
  const std::uint32_t open = stamp_, closed = stamp_ + 1;
  if (marks_[to] == closed) return;
  const int dr = std::abs(to / stride_ - from / stride_), dc = std::abs(to % stride_ - from % stride_);
  // A jump is straight (dr or dc is 0) or diagonal (dr == dc): its cost is its cells' moves.
  const double g = g_[from] + (dr == 0 || dc == 0 ? static_cast<double>(dr + dc) : kDiagonalCost * dr);
  if (marks_[to] == open && g >= g_[to]) return;
  marks_[to] = open;
  g_[to] = g;
  parent_[to] = from;
  const double h = heuristic_distance(heuristic_, to / stride_ - goal_row_, to % stride_ - goal_col_);
  open_.push_back({g + h, to});
  std::push_heap(open_.begin(), open_.end());
}

GridPath JumpPointSearch::search(const BlockedGrid& grid, Cell start, Cell goal, const GridSearchOptions& options) {
  validate(options);
  if (!options.diagonal || options.corner_cutting) {
    throw SchemaError("options", "Jump Point Search is for 8-connected moves without corner cutting");
  }
  check_cell(grid, start, "start", true);
  check_cell(grid, goal, "goal", false);
  GridPath result;
  if (grid.blocked(goal)) return result;

  const std::size_t n = grid.padded().size();
  if (g_.size() != n) {
    g_.assign(n, 0.0);
    parent_.assign(n, -1);
    marks_.assign(n, 0);
    stamp_ = 0;
  }
  if (stamp_ >= std::numeric_limits<std::uint32_t>::max() - 2) {
    std::fill(marks_.begin(), marks_.end(), 0u);
    stamp_ = 0;
  }
  stamp_ += 2;
  open_.clear();
  expanded_ = 0;
  blocked_ = grid.padded().data();
  stride_ = grid.stride();
  heuristic_ = options.heuristic;
  goal_ = grid.index(goal);
  goal_row_ = goal.row + 1;
  goal_col_ = goal.col + 1;
  const std::int32_t source = grid.index(start);
  const std::uint32_t closed = stamp_ + 1;

  g_[source] = 0.0;
  parent_[source] = -1;
  marks_[source] = stamp_;
  open_.push_back({0.0, source});
  bool found = false;
  while (!open_.empty()) {
    std::pop_heap(open_.begin(), open_.end());
    const std::int32_t u = open_.back().node;
    open_.pop_back();
    if (marks_[u] == closed) continue;  // a stale entry
    marks_[u] = closed;
    ++expanded_;
    if (u == goal_) {
      found = true;
      break;
    }
    // The directions worth a jump from u: all eight from the start; else those a shortest path
    // through u's parent may take on from u (natural and forced neighbours).
    int dirs[8][2];
    int count = 0;
    auto add = [&](int dc, int dr) { dirs[count][0] = dc, dirs[count][1] = dr, ++count; };
    const std::int32_t p = parent_[u];
    if (p < 0) {
      for (int dr = -1; dr <= 1; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          if ((dr || dc) && (dr == 0 || dc == 0 || (free(u + dc) && free(u + dr * stride_)))) add(dc, dr);
        }
      }
    } else {
      int dc, dr;
      direction(p, u, dc, dr);
      if (dc != 0 && dr != 0) {
        const bool across = free(u + dc), along = free(u + dr * stride_);
        if (along) add(0, dr);
        if (across) add(dc, 0);
        if (across && along) add(dc, dr);
      } else if (dc != 0) {
        const bool next = free(u + dc), up = free(u + stride_), down = free(u - stride_);
        if (next) {
          add(dc, 0);
          if (up) add(dc, 1);
          if (down) add(dc, -1);
        }
        if (up) add(0, 1);
        if (down) add(0, -1);
      } else {
        const bool next = free(u + dr * stride_), right = free(u + 1), left = free(u - 1);
        if (next) {
          add(0, dr);
          if (right) add(1, dr);
          if (left) add(-1, dr);
        }
        if (right) add(1, 0);
        if (left) add(-1, 0);
      }
    }
    for (int k = 0; k < count; ++k) {
      const int dc = dirs[k][0], dr = dirs[k][1];
      const std::int32_t j = jump(u + dc + dr * stride_, dc, dr);
      if (j >= 0) relax(u, j);
    }
  }
  if (!found) return result;

  // The jump points, from the goal back; then every cell between them (straight or diagonal runs),
  // and the length as A* adds it up, move by move from the start (a diagonal run's k·√2 would
  // differ from k additions of √2 in the last bits).
  std::vector<std::int32_t> points;
  for (std::int32_t v = goal_; v != -1; v = parent_[v]) points.push_back(v);
  std::reverse(points.begin(), points.end());
  result.cells.push_back(grid.cell(points.front()));
  result.length = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) {
    int dc, dr;
    direction(points[i - 1], points[i], dc, dr);
    for (std::int32_t at = points[i - 1]; at != points[i];) {
      at += dc + dr * stride_;
      result.cells.push_back(grid.cell(at));
      result.length += dc != 0 && dr != 0 ? kDiagonalCost : 1.0;
    }
  }
  return result;
}

}  // namespace vwg::plan
