#include "geometry/clearance.hpp"

#include "vwg/geometry/occupancy_grid.hpp"

namespace vwg::geometry {

double clearance(const OccupancyGrid& grid, double x, double y, double limit, int threshold, bool unknown_blocked) {
  double u, v;
  grid.world_to_grid(x, y, u, v);
  const double cap = limit / grid.resolution;
  double d = clearance_to_blocked(u, v, cap, grid.height, grid.width, [&](int r, int c) {
    const int value = grid.at(r, c);
    return value >= threshold || (unknown_blocked && value < 0);
  });
  // Outside the grid is unknown: its squares are as near as the grid's edge (0 once off the grid).
  if (unknown_blocked) d = std::min(d, std::max(0.0, edge_distance(u, v, grid.height, grid.width)));
  return d >= cap ? limit : std::min(limit, d * grid.resolution);
}

}  // namespace vwg::geometry
