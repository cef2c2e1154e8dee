#include "vwg/plan/clearance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vwg::plan {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// One pass of the exact squared Euclidean distance transform of Felzenszwalb & Huttenlocher
/// (2012): d[q] = min over p of (q - p)² + f[p], through the lower envelope of the parabolas
/// rooted at the finite f[p]. `v` and `z` are scratch of n and n + 1 entries.
void distance_transform_1d(const double* f, double* d, int n, std::vector<int>& v, std::vector<double>& z) {
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] == kInf) continue;  // no parabola: keeps ∞ out of the intersection arithmetic
    const double fq = f[q] + static_cast<double>(q) * q;
    double s = -kInf;
    while (k >= 0) {
      const int p = v[k];
      s = (fq - (f[p] + static_cast<double>(p) * p)) / (2.0 * (q - p));
      if (s > z[k]) break;
      --k;
    }
    ++k;
    v[k] = q;
    z[k] = k == 0 ? -kInf : s;
    z[k + 1] = kInf;
  }
  if (k < 0) {
    std::fill(d, d + n, kInf);
    return;
  }
  int j = 0;
  for (int q = 0; q < n; ++q) {
    while (z[j + 1] < q) ++j;
    const double dq = q - v[j];
    d[q] = dq * dq + f[v[j]];
  }
}

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

ClearanceField::ClearanceField(BlockedGrid grid, bool outside_blocked)
    : grid_(std::move(grid)), outside_blocked_(outside_blocked) {
  const int rows = grid_.rows(), cols = grid_.cols();
  const auto at = [cols](int r, int c) { return static_cast<std::size_t>(r) * cols + c; };
  // The distance between two cells' squares is the distance between their centres less one cell
  // on each axis (never below 0). Growing the obstacles by their 8 neighbours subtracts exactly
  // that, so the centre-to-centre transform of the grown mask is the square-to-square distance.
  std::vector<double> f(static_cast<std::size_t>(rows) * cols, kInf);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      bool near = false;
      for (int dr = -1; dr <= 1 && !near; ++dr) {
        for (int dc = -1; dc <= 1 && !near; ++dc) near = grid_.inside({r + dr, c + dc}) && grid_.blocked({r + dr, c + dc});
      }
      if (near) f[at(r, c)] = 0.0;
    }
  }
  const int longest = std::max(rows, cols);
  std::vector<double> line(static_cast<std::size_t>(longest)), out(static_cast<std::size_t>(longest));
  std::vector<int> v(static_cast<std::size_t>(longest));
  std::vector<double> z(static_cast<std::size_t>(longest) + 1);
  for (int c = 0; c < cols; ++c) {  // along columns first, then along rows
    for (int r = 0; r < rows; ++r) line[r] = f[at(r, c)];
    distance_transform_1d(line.data(), out.data(), rows, v, z);
    for (int r = 0; r < rows; ++r) f[at(r, c)] = out[r];
  }
  cell_clearance_.resize(f.size());
  for (int r = 0; r < rows; ++r) {
    distance_transform_1d(&f[at(r, 0)], out.data(), cols, v, z);
    for (int c = 0; c < cols; ++c) cell_clearance_[at(r, c)] = std::sqrt(out[c]);
  }
}

double ClearanceField::edge_distance(double u, double v) const {
  if (!outside_blocked_) return kInf;
  return std::min({u, grid_.cols() - u, v, grid_.rows() - v});
}

double ClearanceField::clearance(double u, double v, double cap) const {
  const double edge = edge_distance(u, v);
  if (edge <= 0.0) return 0.0;
  cap = std::min(cap, edge);
  const int row = static_cast<int>(std::floor(v)), col = static_cast<int>(std::floor(u));
  // Fast path: the whole cell is at least this far from every obstacle.
  if (grid_.inside({row, col}) && cell_clearance({row, col}) >= cap) return cap;
  double best = cap * cap;
  const int margin = static_cast<int>(std::ceil(cap)) + 1;
  const int r0 = std::max(row - margin, 0), r1 = std::min(row + margin, grid_.rows() - 1);
  const int c0 = std::max(col - margin, 0), c1 = std::min(col + margin, grid_.cols() - 1);
  for (int r = r0; r <= r1; ++r) {
    for (int c = c0; c <= c1; ++c) {
      if (grid_.blocked({r, c})) best = std::min(best, squared_distance_to_cell(u, v, {r, c}));
    }
  }
  return std::sqrt(best);
}

bool ClearanceField::piece_clear(double u0, double v0, double u1, double v1, double radius) const {
  const int margin = static_cast<int>(std::ceil(radius)) + 1;
  const int r0 = std::max(static_cast<int>(std::floor(std::min(v0, v1))) - margin, 0);
  const int r1 = std::min(static_cast<int>(std::floor(std::max(v0, v1))) + margin, grid_.rows() - 1);
  const int c0 = std::max(static_cast<int>(std::floor(std::min(u0, u1))) - margin, 0);
  const int c1 = std::min(static_cast<int>(std::floor(std::max(u0, u1))) + margin, grid_.cols() - 1);
  for (int r = r0; r <= r1; ++r) {
    for (int c = c0; c <= c1; ++c) {
      if (grid_.blocked({r, c}) && segment_distance_to_cell(u0, v0, u1, v1, {r, c}) <= radius) return false;
    }
  }
  return true;
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

BlockedGrid inflate(const BlockedGrid& grid, double radius, bool outside_blocked) {
  // A cell's centre is within `radius` of some blocked square iff it is within `radius` of a
  // blocked square on the boundary of the obstacles (one with a free neighbour): from an interior
  // square, its neighbour towards the centre is no farther. So a disc of offsets is stamped around
  // each boundary cell: O(boundary × disc), where testing every cell costs O(cells × disc).
  const int rows = grid.rows(), cols = grid.cols();
  BlockedGrid out(rows, cols);
  if (!(radius >= 0)) return out;
  const int reach = static_cast<int>(std::ceil(radius + 0.5));
  std::vector<Cell> disc;  // offsets whose centre is within radius of the square at (0, 0)
  for (int dr = -reach; dr <= reach; ++dr) {
    for (int dc = -reach; dc <= reach; ++dc) {
      const double ex = std::max(std::abs(dc) - 0.5, 0.0), ey = std::max(std::abs(dr) - 0.5, 0.0);
      if (ex * ex + ey * ey <= radius * radius) disc.push_back({dr, dc});
    }
  }
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
    // The map's edge is an obstacle too: cells whose centre is within radius of it.
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        const double edge = std::min({c + 0.5, cols - c - 0.5, r + 0.5, rows - r - 0.5});
        if (edge <= radius) out.set_blocked({r, c}, true);
      }
    }
  }
  return out;
}

}  // namespace vwg::plan
