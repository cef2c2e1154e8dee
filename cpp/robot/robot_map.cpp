#include "vwg/robot/robot_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vwg/error.hpp"
#include "vwg/geometry/clearance.hpp"

namespace vwg::robot {

std::shared_ptr<Blob> make_robot_map(const geometry::OccupancyGrid& world, bool knows_map, int threshold) {
  auto map = std::make_shared<Blob>(DType::Int16, std::vector<std::int64_t>{world.height, world.width});
  auto cells = map->mutable_view<std::int16_t>();
  if (knows_map) {
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const std::int8_t v = world.data[i];
      cells[i] = v < 0 ? kUnknownCell : (v >= threshold ? kWallCell : kFreeCell);
    }
  }
  return map;
}

namespace {
std::size_t index(const geometry::MapGeometry& g, int row, int col) { return static_cast<std::size_t>(row) * g.width + col; }
std::int16_t cell(const Blob& map, const geometry::MapGeometry& g, int row, int col) {
  return map.view<std::int16_t>()[static_cast<std::size_t>(row) * g.width + col];
}
void check(const Blob& map, const geometry::MapGeometry& g) { check_robot_map(map, g); }

/// A cell walk (Amanatides-Woo) along the segment from (u0, v0) to (u1, v1) in cell units: the
/// cells it crosses, from the start cell to the end cell, in order. The parameter (0 at the start,
/// 1 at the end) at which the segment crosses a grid line is computed from the start for every
/// line, never accumulated step by step, so the walk can jump to where it leaves a block of cells
/// and stand exactly where stepping through the block would have put it. At a grid corner (both
/// lines crossed at once) the row steps first.
struct CellWalk {
  CellWalk(double u0_, double v0_, double u1, double v1)
      : col(static_cast<int>(std::floor(u0_))), end_col(static_cast<int>(std::floor(u1))),
        row(static_cast<int>(std::floor(v0_))), end_row(static_cast<int>(std::floor(v1))), col0(col), row0(row),
        u0(u0_), v0(v0_) {
    const double du = u1 - u0, dv = v1 - v0;
    step_u = du > 0 ? 1 : -1;
    step_v = dv > 0 ? 1 : -1;
    exit_u = du > 0 ? 1 : 0;
    exit_v = dv > 0 ? 1 : 0;
    moves_u = du != 0;
    moves_v = dv != 0;
    inv_du = moves_u ? 1.0 / du : 0.0;
    inv_dv = moves_v ? 1.0 / dv : 0.0;
    t_u = crossing_u(col + exit_u);
    t_v = crossing_v(row + exit_v);
  }
  /// Cells from the start to the end cell, both counted, on a straight walk.
  int length() const { return std::abs(end_col - col) + std::abs(end_row - row) + 1; }
  bool at_end() const { return col == end_col && row == end_row; }
  /// Where the segment crosses the column line `line` / the row line `line` (infinity if never).
  double crossing_u(int line) const { return moves_u ? (line - u0) * inv_du : kNever; }
  double crossing_v(int line) const { return moves_v ? (line - v0) * inv_dv : kNever; }
  /// Whether the walk, from its start on and never stopping, passes through cell (r, c).
  bool visits(int r, int c) const {
    // The walk is in column c between the crossings of the line into it and the line out of it
    // (the start column from the outset), and likewise in row r; at a grid corner the row line is
    // crossed first. It is in the cell while in both.
    struct Key {  // a crossing, in the walk's order
      double t;
      int row_first;
      bool operator<(const Key& o) const { return t < o.t || (t == o.t && row_first < o.row_first); }
    };
    const auto span = [](int cell, int first, int step, int exit, bool moves, auto crossing, int order, Key& in, Key& out) {
      if ((cell - first) * step < 0 || (!moves && cell != first)) return false;
      in = cell == first ? Key{-kNever, order} : Key{crossing(cell - step + exit), order};
      out = Key{crossing(cell + exit), order};
      return true;
    };
    Key in_u, out_u, in_v, out_v;
    if (!span(c, col0, step_u, exit_u, moves_u, [this](int line) { return crossing_u(line); }, 1, in_u, out_u)) return false;
    if (!span(r, row0, step_v, exit_v, moves_v, [this](int line) { return crossing_v(line); }, 0, in_v, out_v)) return false;
    const Key& in = in_u < in_v ? in_v : in_u;
    const Key& out = out_u < out_v ? out_u : out_v;
    return in < out;
  }
  void advance() {
    if (t_u < t_v) {
      col += step_u;
      t_u = crossing_u(col + exit_u);
    } else {
      row += step_v;
      t_v = crossing_v(row + exit_v);
    }
  }
  /// Leave the block of `side` × `side` cells (side a power of two, `shift` its log) holding the
  /// current cell: stand on the first cell past it, as that many advance() calls would. Returns
  /// how many cells it moved.
  int leave_block(int shift) {
    const int side = 1 << shift;
    // The block's far lines the way the walk goes, and where the walk crosses them.
    const int far_u = ((col >> shift) + exit_u) * side, far_v = ((row >> shift) + exit_v) * side;
    const double leave_u = crossing_u(far_u), leave_v = crossing_v(far_v);
    const int was_col = col, was_row = row;
    if (leave_u < leave_v) {
      // Out through the column line: every row line crossed at or before it (the row steps first
      // at a corner) has been crossed by then.
      while (t_v <= leave_u) row += step_v, t_v = crossing_v(row + exit_v);
      col = step_u > 0 ? far_u : far_u - 1;
      t_u = crossing_u(col + exit_u);
    } else {
      // Out through the row line: the column lines crossed strictly before it.
      while (t_u < leave_v) col += step_u, t_u = crossing_u(col + exit_u);
      row = step_v > 0 ? far_v : far_v - 1;
      t_v = crossing_v(row + exit_v);
    }
    return std::abs(col - was_col) + std::abs(row - was_row);
  }

  static constexpr double kNever = std::numeric_limits<double>::infinity();
  // Not {col, row} beside {end_col, end_row}: GCC then compares the pairs as one 8-byte word read
  // back from the stack, a store-forwarding stall on every step (the walk ran at half speed).
  int col;
  const int end_col;
  int row;
  const int end_row;
  const int col0, row0;  // the start cell
  double u0, v0;
  int step_u, step_v, exit_u, exit_v;
  bool moves_u, moves_v;
  double inv_du, inv_dv, t_u, t_v;
};
}  // namespace

void check_robot_map(const Blob& map, const geometry::MapGeometry& g) {
  if (map.dtype() != DType::Int16 || map.ndim() != 2 || map.shape()[0] != g.height || map.shape()[1] != g.width) {
    throw SchemaError("grid", "a robot map is an int16 array of the world map's shape");
  }
}

void ObstacleBits::sync(const Blob& map, const geometry::MapGeometry& g) {
  check(map, g);
  const int columns = (g.width + (1 << kShift) - 1) >> kShift, rows = (g.height + (1 << kShift) - 1) >> kShift;
  if (revision_ == map.revision() && columns == columns_ && seen_.size() == static_cast<std::size_t>(rows) * columns) return;
  columns_ = columns;
  rows_ = rows;
  seen_.assign(static_cast<std::size_t>(rows) * columns, 0);
  obstacle_.assign(seen_.size(), 0);
  blocks_.assign((seen_.size() + 63) / 64, 0);
  lo_row_ = lo_col_ = std::numeric_limits<int>::max();
  hi_row_ = hi_col_ = std::numeric_limits<int>::min();
  const auto cells = map.view<std::int16_t>();
  for (int r = 0; r < g.height; ++r) {
    for (int c = 0; c < g.width; ++c) {
      if (const std::int16_t v = cells[index(g, r, c)]; is_obstacle(v)) set(r, c, v);
    }
  }
  revision_ = map.revision();
}

bool mark_obstacle(MapEdit& map, const geometry::MapGeometry& g, double x, double y, ObstacleBits* bits) {
  check(map.blob(), g);
  int r, c;
  if (!g.cell_of(x, y, r, c)) return false;
  if (bits ? bits->obstacle(r, c) : is_obstacle(map[index(g, r, c)])) return false;  // walls and markers stay
  map.set(index(g, r, c), kSeenCell);
  if (bits) bits->set(r, c, kSeenCell);
  return true;
}

bool mark_marker(MapEdit& map, const geometry::MapGeometry& g, double x, double y, int tag, ObstacleBits* bits) {
  check(map.blob(), g);
  int r, c;
  if (!g.cell_of(x, y, r, c)) return false;
  const auto value = static_cast<std::int16_t>(kMarkerBase + tag);
  if (map[index(g, r, c)] == value) return false;
  map.set(index(g, r, c), value);
  if (bits) bits->set(r, c, value);
  return true;
}

int carve_free(MapEdit& map, const geometry::MapGeometry& g, double x0, double y0, double x1, double y1, ObstacleBits* bits) {
  check(map.blob(), g);
  const geometry::OccupancyGrid f = g.frame();
  double u0, v0, u1, v1;
  f.world_to_grid(x0, y0, u0, v0);
  f.world_to_grid(x1, y1, u1, v1);
  // The cells the beam crossed, from the start cell to the end cell, which is left alone.
  CellWalk walk(u0, v0, u1, v1);
  const int limit = walk.length() + 1;
  // No reported obstacle in the walk's box of cells: nothing to clear.
  if (bits && !bits->may_hold(std::min(walk.row, walk.end_row), std::min(walk.col, walk.end_col),
                              std::max(walk.row, walk.end_row), std::max(walk.col, walk.end_col))) {
    return 0;
  }
  constexpr int kShift = ObstacleBits::kShift;
  const int end_block_row = walk.end_row >> kShift, end_block_col = walk.end_col >> kShift;
  const auto rows = static_cast<unsigned>(g.height), cols = static_cast<unsigned>(g.width);
  int changed = 0;
  for (int k = 0; k < limit && !walk.at_end();) {
    const int row = walk.row, col = walk.col;
    if (bits && !bits->block_seen(row, col)) {
      // A block with no reported obstacle: out of it in one jump (most of a beam's way is such
      // blocks). If the walk ends in it, it reaches the end cell without leaving it (the block is
      // a box, the walk monotone), so nothing more is cleared; unless rounding makes it miss the
      // end cell, then it goes on cell by cell, reading nothing here.
      if ((row >> kShift) != end_block_row || (col >> kShift) != end_block_col) {
        k += walk.leave_block(kShift);
        continue;
      }
      if (walk.visits(walk.end_row, walk.end_col)) return changed;
    } else if (static_cast<unsigned>(row) < rows && static_cast<unsigned>(col) < cols &&
               (bits ? bits->seen(row, col) : map[index(g, row, col)] == kSeenCell)) {
      map.set(index(g, row, col), kFreeCell);
      if (bits) bits->set(row, col, kFreeCell);
      ++changed;
    }
    walk.advance();
    ++k;
  }
  return changed;
}

bool segment_clear(const Blob& map, const geometry::MapGeometry& g, double x0, double y0, double x1, double y1, double radius,
                   bool unknown_blocked) {
  check(map, g);
  const geometry::OccupancyGrid f = g.frame();
  double u0, v0, u1, v1;
  f.world_to_grid(x0, y0, u0, v0);
  f.world_to_grid(x1, y1, u1, v1);
  const double rc = radius / g.resolution;
  // Touching is allowed: `radius` already holds the margin the robot keeps (ARobotConfig::margin).
  const bool clear = geometry::segment_clear_of_blocked(u0, v0, u1, v1, rc, geometry::Touch::Allowed, g.height, g.width,
                                                        [&](int r, int c) {
                                                          const std::int16_t v = cell(map, g, r, c);
                                                          return is_obstacle(v) || (unknown_blocked && v == kUnknownCell);
                                                        });
  // Leaving the map is not allowed either.
  return clear && u0 >= rc && v0 >= rc && u1 >= rc && v1 >= rc && u0 <= g.width - rc && u1 <= g.width - rc &&
         v0 <= g.height - rc && v1 <= g.height - rc;
}

double clearance(const Blob& map, const geometry::MapGeometry& g, double x, double y, double cap) {
  check(map, g);
  double u, v;
  g.frame().world_to_grid(x, y, u, v);
  const double rc = cap / g.resolution;
  return geometry::clearance_to_blocked(u, v, rc, g.height, g.width, [&](int r, int c) { return is_obstacle(cell(map, g, r, c)); }) *
         g.resolution;
}

bool find_marker(const Blob& map, const geometry::MapGeometry& g, int tag, double& x, double& y) {
  check(map, g);
  const auto cells = map.view<std::int16_t>();
  const auto value = static_cast<std::int16_t>(kMarkerBase + tag);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (cells[i] == value) {
      g.centre_of(static_cast<int>(i / g.width), static_cast<int>(i % g.width), x, y);
      return true;
    }
  }
  return false;
}

}  // namespace vwg::robot
