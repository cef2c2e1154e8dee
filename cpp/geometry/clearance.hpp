// How far a point or a segment is from the blocked cells around it: the one brute-force scan that
// the robot's map, the planners' distance field and the Python maps all ask. The grid is given as a
// predicate so that each caller keeps its own cells (int16 robot maps, BlockedGrid, int8 maps)
// without copying them into a mask per query.
// Private to vwg's libraries (beside their sources, under cpp/): not installed.
#pragma once

#include <algorithm>
#include <cmath>

#include "geometry/cell_distance.hpp"

namespace vwg::geometry {

/// The distance (cells) from (u, v) to the nearest square of a rows × cols grid for which
/// `blocked(row, col)`, or `cap` if none is nearer. Only cells inside the grid are asked (the map's
/// edge is the caller's business). The work grows with cap²: ask only as far as needed.
template <class Blocked>
double clearance_to_blocked(double u, double v, double cap, int rows, int cols, Blocked&& blocked) {
  const int row = static_cast<int>(std::floor(v)), col = static_cast<int>(std::floor(u));
  // One cell more than the cap on each side, so rounding in the window cannot leave a square out.
  const int margin = static_cast<int>(std::ceil(cap)) + 1;
  const int r0 = std::max(row - margin, 0), r1 = std::min(row + margin, rows - 1);
  const int c0 = std::max(col - margin, 0), c1 = std::min(col + margin, cols - 1);
  double best = cap * cap;
  for (int r = r0; r <= r1; ++r) {
    for (int c = c0; c <= c1; ++c) {
      if (blocked(r, c)) best = std::min(best, squared_distance_to_cell(u, v, Cell{r, c}));
    }
  }
  return std::sqrt(best);  // sqrt(cap * cap) is cap exactly (IEEE): uncapped results are unchanged
}

/// Whether a disc of `radius` (cells) may touch an obstacle (its boundary at exactly `radius`).
enum class Touch {
  Allowed,  ///< blocked when a square is closer than radius (the robot's own map: its radius holds a margin)
  Refused,  ///< blocked when a square is at most radius away (OMPL's validity: clearance > radius)
};

/// The squares segment_clear_of_blocked looks at: rows r0..r1, columns c0..c1 (empty when r0 > r1).
struct CellWindow {
  int r0, r1, c0, c1;
  bool holds(int row, int col) const { return row >= r0 && row <= r1 && col >= c0 && col <= c1; }
};

/// The squares within reach of a disc of `radius` cells swept along (u0, v0)–(u1, v1): those near its bounding box.
inline CellWindow segment_window(double u0, double v0, double u1, double v1, double radius, int rows, int cols) {
  const int margin = static_cast<int>(std::ceil(radius)) + 1;
  return CellWindow{std::max(static_cast<int>(std::floor(std::min(v0, v1))) - margin, 0),
                    std::min(static_cast<int>(std::floor(std::max(v0, v1))) + margin, rows - 1),
                    std::max(static_cast<int>(std::floor(std::min(u0, u1))) - margin, 0),
                    std::min(static_cast<int>(std::floor(std::max(u0, u1))) + margin, cols - 1)};
}

/// Whether the segment (u0, v0)–(u1, v1) stays clear of every square of a rows × cols grid for which
/// `blocked(row, col)`, by `radius` cells under the `touch` rule. Every square of segment_window is
/// tested exactly (no sampling), so keep segments short or the grid sparse.
template <class Blocked>
bool segment_clear_of_blocked(double u0, double v0, double u1, double v1, double radius, Touch touch, int rows, int cols,
                              Blocked&& blocked) {
  const auto [r0, r1, c0, c1] = segment_window(u0, v0, u1, v1, radius, rows, cols);
  for (int r = r0; r <= r1; ++r) {
    for (int c = c0; c <= c1; ++c) {
      if (!blocked(r, c)) continue;
      const double d = segment_distance_to_cell(u0, v0, u1, v1, Cell{r, c});
      if (touch == Touch::Allowed ? d < radius : d <= radius) return false;
    }
  }
  return true;
}

/// The distance (cells) from (u, v) to the edge of a rows × cols grid: negative outside it.
inline double edge_distance(double u, double v, int rows, int cols) { return std::min({u, cols - u, v, rows - v}); }

/// The clearance of the world point (x, y) on an occupancy grid, in metres and capped at `limit`:
/// the distance to the nearest cell of value ≥ `threshold` (or unknown, < 0, when `unknown_blocked`,
/// which also makes everything outside the grid an obstacle). 0 inside an obstacle.
double clearance(const OccupancyGrid& grid, double x, double y, double limit, int threshold = kObstacleThreshold, bool unknown_blocked = true);

}  // namespace vwg::geometry
