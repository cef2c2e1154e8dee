#include "vwg/geometry/clearance_field.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/clearance.hpp"
#include "geometry/distance_transform.hpp"
#include "geometry/inflate.hpp"

namespace vwg::geometry {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

ClearanceField::ClearanceField(BlockedGrid grid, bool outside_blocked)
    : grid_(std::move(grid)), outside_blocked_(outside_blocked) {
  const int rows = grid_.rows(), cols = grid_.cols();
  const auto at = [cols](int r, int c) { return static_cast<std::size_t>(r) * cols + c; };
  // The distance between two cells' squares is the distance between their centres less one cell
  // on each axis (never below 0). Growing the obstacles by their 8 neighbours subtracts exactly
  // that, so the centre-to-centre transform of the grown mask is the square-to-square distance.
  std::vector<std::uint8_t> grown(static_cast<std::size_t>(rows) * cols, 0);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      bool near = false;
      for (int dr = -1; dr <= 1 && !near; ++dr) {
        for (int dc = -1; dc <= 1 && !near; ++dc) near = grid_.inside({r + dr, c + dc}) && grid_.blocked({r + dr, c + dc});
      }
      grown[at(r, c)] = near ? 1 : 0;
    }
  }
  cell_clearance_ = squared_distance_transform(grown, rows, cols);
  for (double& d : cell_clearance_) d = std::sqrt(d);
}

double ClearanceField::edge_distance(double u, double v) const {
  if (!outside_blocked_) return kInf;
  return geometry::edge_distance(u, v, grid_.rows(), grid_.cols());
}

double ClearanceField::clearance(double u, double v, double cap) const {
  const double edge = edge_distance(u, v);
  if (edge <= 0.0) return 0.0;
  cap = std::min(cap, edge);
  const int row = static_cast<int>(std::floor(v)), col = static_cast<int>(std::floor(u));
  // Fast path: the whole cell is at least this far from every obstacle.
  if (grid_.inside({row, col}) && cell_clearance({row, col}) >= cap) return cap;
  return clearance_to_blocked(u, v, cap, grid_.rows(), grid_.cols(), [this](int r, int c) { return grid_.blocked({r, c}); });
}

bool ClearanceField::piece_clear(double u0, double v0, double u1, double v1, double radius) const {
  return segment_clear_of_blocked(u0, v0, u1, v1, radius, Touch::Refused, grid_.rows(), grid_.cols(),
                                  [this](int r, int c) { return grid_.blocked({r, c}); });
}

bool ClearanceField::segment_clear(double u0, double v0, double u1, double v1, double radius) const {
  // The distance to the map's edge is concave along a segment inside it: checking the ends suffices.
  if (edge_distance(u0, v0) <= radius || edge_distance(u1, v1) <= radius) return false;
  const double length = std::hypot(u1 - u0, v1 - v0);
  if (length == 0.0) return piece_clear(u0, v0, u0, v0, radius);
  const double du = (u1 - u0) / length, dv = (v1 - v0) / length;
  // Pieces tested square by square are one cell long; a free step is taken only when it is longer.
  constexpr double kPiece = 1.0;
  double t = 0.0;
  while (t < length) {
    const double u = u0 + du * t, v = v0 + dv * t;
    const Cell cell{static_cast<int>(std::floor(v)), static_cast<int>(std::floor(u))};
    if (grid_.inside(cell)) {
      // Every point within cell_clearance of (u, v) is free, so the disc can travel that far less
      // its radius before it could touch anything.
      const double free_run = cell_clearance(cell) - radius;
      if (free_run >= kPiece) {
        t += free_run;
        continue;
      }
    }
    const double end = std::min(length, t + kPiece);
    if (!piece_clear(u, v, u0 + du * end, v0 + dv * end, radius)) return false;
    t = end;
  }
  return true;
}

BlockedGrid ClearanceField::inflated(double radius) const { return inflate(grid_, radius, outside_blocked_); }

}  // namespace vwg::geometry
