#include "geometry/cell_distance.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace vwg::geometry {

namespace {

double squared_point_segment(double px, double py, double ax, double ay, double bx, double by) {
  const double dx = bx - ax, dy = by - ay;
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0.0 ? ((px - ax) * dx + (py - ay) * dy) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  const double ex = ax + t * dx - px, ey = ay + t * dy - py;
  return ex * ex + ey * ey;
}

}  // namespace

double squared_distance_to_cell(double u, double v, Cell cell) {
  const double dx = std::max({cell.col - u, 0.0, u - (cell.col + 1)});
  const double dy = std::max({cell.row - v, 0.0, v - (cell.row + 1)});
  return dx * dx + dy * dy;
}

double segment_distance_to_cell(double u0, double v0, double u1, double v1, Cell cell) {
  // Do they meet? Clip the segment's parameter range against the square's two slabs.
  const double lo[2] = {static_cast<double>(cell.col), static_cast<double>(cell.row)};
  const double a[2] = {u0, v0}, d[2] = {u1 - u0, v1 - v0};
  double t0 = 0.0, t1 = 1.0;
  bool meet = true;
  for (int axis = 0; axis < 2 && meet; ++axis) {
    if (d[axis] == 0.0) {
      meet = a[axis] >= lo[axis] && a[axis] <= lo[axis] + 1.0;
    } else {
      double ta = (lo[axis] - a[axis]) / d[axis], tb = (lo[axis] + 1.0 - a[axis]) / d[axis];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      meet = t0 <= t1;
    }
  }
  if (meet) return 0.0;
  // Apart, two convex sets are closest at a vertex of one of them: an end of the segment or a
  // corner of the square.
  double best = std::min(squared_distance_to_cell(u0, v0, cell), squared_distance_to_cell(u1, v1, cell));
  for (int corner = 0; corner < 4; ++corner) {
    const double cx = cell.col + (corner & 1), cy = cell.row + (corner >> 1);
    best = std::min(best, squared_point_segment(cx, cy, u0, v0, u1, v1));
  }
  return std::sqrt(best);
}

}  // namespace vwg::geometry
