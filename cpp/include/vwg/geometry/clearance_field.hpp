// A distance field over the blocked cells of a grid: exact clearance and swept-disc segment tests
// for the sampling-based planners, answered at once far from obstacles.
#pragma once

#include <vector>

#include "vwg/geometry/blocked_grid.hpp"

namespace vwg::geometry {

/// Distances to the blocked cells of a grid, in cells. Points are in continuous grid coordinates:
/// u along columns, v along rows, cell (r, c) being the closed square [c, c+1] × [r, r+1] (as
/// OccupancyGrid::world_to_grid gives them). A precomputed distance transform answers most
/// queries at once; near obstacles the exact distance to the few blocked squares around is computed.
class ClearanceField {
 public:
  ClearanceField() = default;
  /// `outside_blocked`: everything outside the grid counts as an obstacle, so a robot stays on the map.
  explicit ClearanceField(BlockedGrid grid, bool outside_blocked = true);

  const BlockedGrid& grid() const { return grid_; }
  bool outside_blocked() const { return outside_blocked_; }

  /// The exact distance from (u, v) to the nearest blocked square (or the map's edge when outside
  /// is blocked), or `cap` if that is smaller: the work grows with cap², so ask only as far as needed.
  /// 0 inside a blocked cell or off the map.
  double clearance(double u, double v, double cap) const;

  /// Whether every point of the segment from (u0, v0) to (u1, v1) is farther than `radius` from
  /// every blocked square and the map's edge: a disc of that radius swept along it does not even
  /// touch an obstacle (so with radius 0 a segment may not run along a blocked cell's side).
  /// Exact (no sampling): far from obstacles the segment is crossed in steps as long as the free
  /// distance allows; near them, each short piece is tested against every blocked square around it.
  bool segment_clear(double u0, double v0, double u1, double v1, double radius) const;

  /// A lower bound on the clearance of every point of cell `c` (ignoring the map's edge): the
  /// distance from its square to the nearest blocked square. 0 for blocked cells and their neighbours.
  double cell_clearance(Cell c) const { return cell_clearance_[static_cast<std::size_t>(c.row) * grid_.cols() + c.col]; }

  /// The cells whose centre is no farther than `radius` from an obstacle: where the centre of a
  /// disc of that radius may not be (as the planners' validity test says), as a grid for A* or D* Lite.
  BlockedGrid inflated(double radius) const;

 private:
  /// Whether the piece of segment (u0, v0)–(u1, v1) stays farther than `radius` from every blocked
  /// square of its neighbourhood (the squares are enumerated, so keep pieces short).
  bool piece_clear(double u0, double v0, double u1, double v1, double radius) const;
  double edge_distance(double u, double v) const;

  BlockedGrid grid_;
  bool outside_blocked_ = true;
  std::vector<double> cell_clearance_;  ///< rows × cols, row-major
};

}  // namespace vwg::geometry
