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
/// cells it crosses, from the start cell to the end cell, in order.
struct CellWalk {
  CellWalk(double u0, double v0, double u1, double v1)
      : col(static_cast<int>(std::floor(u0))), end_col(static_cast<int>(std::floor(u1))),
        row(static_cast<int>(std::floor(v0))), end_row(static_cast<int>(std::floor(v1))) {
    const double du = u1 - u0, dv = v1 - v0;
    const double inf = std::numeric_limits<double>::infinity();
    step_u = du > 0 ? 1 : -1;
    step_v = dv > 0 ? 1 : -1;
    delta_u = du != 0 ? std::abs(1.0 / du) : inf;
    delta_v = dv != 0 ? std::abs(1.0 / dv) : inf;
    t_u = du != 0 ? ((du > 0 ? std::floor(u0) + 1 - u0 : u0 - std::floor(u0)) * delta_u) : inf;
    t_v = dv != 0 ? ((dv > 0 ? std::floor(v0) + 1 - v0 : v0 - std::floor(v0)) * delta_v) : inf;
  }
  /// Cells from the start to the end cell, both counted, on a straight walk.
  int length() const { return std::abs(end_col - col) + std::abs(end_row - row) + 1; }
  bool at_end() const { return col == end_col && row == end_row; }
  void advance() {
    if (t_u < t_v) {
      t_u += delta_u;
      col += step_u;
    } else {
      t_v += delta_v;
      row += step_v;
    }
  }

  // Not {col, row} beside {end_col, end_row}: GCC then compares the pairs as one 8-byte word read
  // back from the stack, a store-forwarding stall on every step (the walk ran at half speed).
  int col;
  const int end_col;
  int row;
  const int end_row;
  int step_u, step_v;
  double delta_u, delta_v, t_u, t_v;
};
}  // namespace

void check_robot_map(const Blob& map, const geometry::MapGeometry& g) {
  if (map.dtype() != DType::Int16 || map.ndim() != 2 || map.shape()[0] != g.height || map.shape()[1] != g.width) {
    throw SchemaError("grid", "a robot map is an int16 array of the world map's shape");
  }
}

void SeenBlocks::sync(const Blob& map, const geometry::MapGeometry& g) {
  check(map, g);
  const int columns = (g.width + (1 << kShift) - 1) >> kShift, rows = (g.height + (1 << kShift) - 1) >> kShift;
  if (revision_ == map.revision() && columns == columns_ && counts_.size() == static_cast<std::size_t>(rows) * columns) return;
  columns_ = columns;
  rows_ = rows;
  counts_.assign(static_cast<std::size_t>(rows) * columns, 0);
  lo_row_ = lo_col_ = std::numeric_limits<int>::max();
  hi_row_ = hi_col_ = std::numeric_limits<int>::min();
  const auto cells = map.view<std::int16_t>();
  for (int r = 0; r < g.height; ++r) {
    for (int c = 0; c < g.width; ++c) {
      if (cells[index(g, r, c)] == kSeenCell) added(r, c);
    }
  }
  revision_ = map.revision();
}

bool SeenBlocks::along(double u0, double v0, double u1, double v1) const {
  const double size = 1 << kShift;
  CellWalk block(u0 / size, v0 / size, u1 / size, v1 / size);  // a walk over blocks
  auto holds = [&](int br, int bc) {
    return br >= 0 && bc >= 0 && br < rows_ && bc < columns_ &&
           counts_[static_cast<std::size_t>(br) * static_cast<std::size_t>(columns_) + static_cast<std::size_t>(bc)] != 0;
  };
  const int limit = block.length();
  for (int k = 0; k < limit; ++k) {
    const int r = block.row, c = block.col;
    if (holds(r, c) || holds(r - 1, c) || holds(r + 1, c) || holds(r, c - 1) || holds(r, c + 1)) return true;
    if (block.at_end()) break;
    block.advance();
  }
  return false;
}

bool mark_obstacle(MapEdit& map, const geometry::MapGeometry& g, double x, double y, SeenBlocks* seen) {
  check(map.blob(), g);
  int r, c;
  if (!g.cell_of(x, y, r, c)) return false;
  if (is_obstacle(map[index(g, r, c)])) return false;  // walls and markers stay
  map.set(index(g, r, c), kSeenCell);
  if (seen) seen->added(r, c);
  return true;
}

bool mark_marker(MapEdit& map, const geometry::MapGeometry& g, double x, double y, int tag, SeenBlocks* seen) {
  check(map.blob(), g);
  int r, c;
  if (!g.cell_of(x, y, r, c)) return false;
  const auto value = static_cast<std::int16_t>(kMarkerBase + tag);
  const std::int16_t was = map[index(g, r, c)];
  if (was == value) return false;
  map.set(index(g, r, c), value);
  if (seen && was == kSeenCell) seen->removed(r, c);
  return true;
}

int carve_free(MapEdit& map, const geometry::MapGeometry& g, double x0, double y0, double x1, double y1, SeenBlocks* seen) {
  check(map.blob(), g);
  const geometry::OccupancyGrid f = g.frame();
  double u0, v0, u1, v1;
  f.world_to_grid(x0, y0, u0, v0);
  f.world_to_grid(x1, y1, u1, v1);
  // The cells the beam crossed, from the start cell to the end cell, which is left alone.
  CellWalk walk(u0, v0, u1, v1);
  const int limit = walk.length() + 1;
  // No reported obstacle in the walk's box of cells: nothing to clear.
  if (seen && (!seen->may_hold(std::min(walk.row, walk.end_row), std::min(walk.col, walk.end_col),
                               std::max(walk.row, walk.end_row), std::max(walk.col, walk.end_col)) ||
               !seen->along(u0, v0, u1, v1))) {
    return 0;
  }
  const std::int16_t* cells = map.view().data();
  const auto rows = static_cast<unsigned>(g.height), cols = static_cast<unsigned>(g.width);
  int changed = 0;
  int k = 0;
  while (true) {
    // To the next cell holding a reported obstacle, with no call in the loop (it stays in registers).
    bool found = false;
    for (; k < limit && !walk.at_end(); walk.advance(), ++k) {
      if (static_cast<unsigned>(walk.row) < rows && static_cast<unsigned>(walk.col) < cols &&
          (!seen || seen->any(walk.row, walk.col)) && cells[index(g, walk.row, walk.col)] == kSeenCell) {
        found = true;
        break;
      }
    }
    if (!found) return changed;
    map.set(index(g, walk.row, walk.col), kFreeCell);
    if (seen) seen->removed(walk.row, walk.col);
    ++changed;
    walk.advance();
    ++k;
  }
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
