// Inflation: the cells where the centre of a disc-shaped robot may not be, the configuration space
// the grid planners search.
// Private to vwg's libraries (beside their sources, under cpp/): not installed.
#pragma once

#include <algorithm>
#include <vector>

#include "vwg/geometry/blocked_grid.hpp"

namespace vwg::geometry {

/// The offsets (dr, dc) of the cells whose centre is within `radius` (cells, inclusive) of the
/// square of cell (0, 0): what one blocked cell adds to the inflated grid. Empty for a negative radius.
std::vector<Cell> inflation_disc(double radius);

/// Whether the centre of cell (row, col) is within `radius` (inclusive) of the edge of a rows × cols grid.
inline bool centre_near_edge(int row, int col, int rows, int cols, double radius) {
  return std::min({col + 0.5, cols - col - 0.5, row + 0.5, rows - row - 0.5}) <= radius;
}

/// The cells whose centre is within `radius` (cells, inclusive) of a blocked square — or of the
/// map's edge when `outside_blocked`. A negative (or NaN) radius inflates nothing: the blocked
/// cells themselves, as radius 0.
BlockedGrid inflate(const BlockedGrid& grid, double radius, bool outside_blocked = true);

}  // namespace vwg::geometry
