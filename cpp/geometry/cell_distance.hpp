// Exact distances from points and segments to the squares of grid cells, in continuous grid
// coordinates: u along columns, v along rows, cell (r, c) being the closed square [c, c+1] × [r, r+1]
// (as OccupancyGrid::world_to_grid gives them).
// Private to vwg's libraries (beside their sources, under cpp/): not installed.
#pragma once

#include "vwg/geometry/blocked_grid.hpp"

namespace vwg::geometry {

/// The squared distance from point (u, v) to the square of `cell`.
double squared_distance_to_cell(double u, double v, Cell cell);
/// The distance from the segment (u0, v0)–(u1, v1) to the square of `cell` (0 if they meet).
double segment_distance_to_cell(double u0, double v0, double u1, double v1, Cell cell);

}  // namespace vwg::geometry
