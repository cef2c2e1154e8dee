#include "geometry/inflate.hpp"

#include <cmath>
#include <cstdlib>

namespace vwg::geometry {

std::vector<Cell> inflation_disc(double radius) {
  std::vector<Cell> disc;
  if (!(radius >= 0)) return disc;
  const int reach = static_cast<int>(std::ceil(radius + 0.5));
  for (int dr = -reach; dr <= reach; ++dr) {
    for (int dc = -reach; dc <= reach; ++dc) {
      const double ex = std::max(std::abs(dc) - 0.5, 0.0), ey = std::max(std::abs(dr) - 0.5, 0.0);
      if (ex * ex + ey * ey <= radius * radius) disc.push_back({dr, dc});
    }
  }
  return disc;
}

BlockedGrid inflate(const BlockedGrid& grid, double radius, bool outside_blocked) {
  // A cell's centre is within `radius` of some blocked square iff it is within `radius` of a
  // blocked square on the boundary of the obstacles (one with a free neighbour): from an interior
  // square, its neighbour towards the centre is no farther. So a disc of offsets is stamped around
  // each boundary cell: O(boundary × disc), where testing every cell costs O(cells × disc).
  if (!(radius >= 0)) radius = 0.0;  // a robot may still not stand in a wall
  const int rows = grid.rows(), cols = grid.cols();
  BlockedGrid out(rows, cols);
  const std::vector<Cell> disc = inflation_disc(radius);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (!grid.blocked({r, c})) continue;
      bool boundary = false;
      for (int dr = -1; dr <= 1 && !boundary; ++dr) {
        for (int dc = -1; dc <= 1 && !boundary; ++dc) {
          const Cell n{r + dr, c + dc};
          boundary = grid.inside(n) && !grid.blocked(n);
        }
      }
      if (!boundary) {
        out.set_blocked({r, c}, true);
        continue;
      }
      for (const Cell& d : disc) {
        const Cell n{r + d.row, c + d.col};
        if (grid.inside(n)) out.set_blocked(n, true);
      }
    }
  }
  if (outside_blocked) {
    // The map's edge is an obstacle too.
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        if (centre_near_edge(r, c, rows, cols, radius)) out.set_blocked({r, c}, true);
      }
    }
  }
  return out;
}

}  // namespace vwg::geometry
