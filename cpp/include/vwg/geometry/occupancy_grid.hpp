// Occupancy grids: the map every simulated sensor, the physics world, the renderers, the planners
// and the robots share.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "vwg/geometry/pose.hpp"

namespace vwg::geometry {

/// Values of an occupancy grid cell (nav_msgs/OccupancyGrid): -1 unknown, 0 free, 100 occupied;
/// maps loaded in "scale" mode hold values in between.
inline constexpr std::int8_t kUnknown = -1;
inline constexpr std::int8_t kFree = 0;
inline constexpr std::int8_t kOccupied = 100;

/// The value from which a cell is an obstacle unless said otherwise: occupied cells and the upper
/// half of a "scale" map.
inline constexpr int kObstacleThreshold = 50;

/// Whether a cell value is an obstacle: at least `threshold` (100 = occupied; 50 also counts the
/// upper half of "scale" maps), or unknown (negative) when `unknown` is set. The one rule of the
/// grids' masks (OccupancyGrid::blocked, BlockedGrid::from_occupancy, vwg.maps.OccupancyGrid.blocked).
inline bool blocked_value(int value, int threshold, bool unknown) { return value >= threshold || (unknown && value < 0); }

/// floor(t) as a cell number. A point so far away that this is not a number an int64 holds (or t
/// is not finite) gets ±2^62 (-2^62 for NaN): a cell outside every grid, instead of an overflow.
inline std::int64_t cell_index(double t) {
  constexpr double kFar = 4611686018427387904.0;  // 2^62
  if (!(t > -kFar)) return -(std::int64_t{1} << 62);
  if (!(t < kFar)) return std::int64_t{1} << 62;
  return static_cast<std::int64_t>(std::floor(t));
}

/// A grid in nav_msgs/OccupancyGrid order: row-major, row 0 is the bottom row of the map (smallest
/// y), column 0 the left column. `origin` is the pose of the lower-left corner of cell (0, 0), as
/// map_server's `origin`; cell (r, c) covers [c, c+1) × [r, r+1) cells in the map frame.
struct OccupancyGrid {
  int width = 0;   ///< columns
  int height = 0;  ///< rows
  double resolution = 0.05;  ///< metres per cell
  Pose2 origin{};
  std::vector<std::int8_t> data;  ///< width * height values

  bool inside(int row, int col) const { return row >= 0 && col >= 0 && row < height && col < width; }
  std::int8_t at(int row, int col) const { return data[static_cast<std::size_t>(row) * width + col]; }
  /// An obstacle for simulation: a value of at least `threshold` (100 = occupied; 50 also
  /// counts the upper half of "scale" maps). Unknown and outside cells are not obstacles.
  bool blocked(int row, int col, int threshold = kObstacleThreshold) const {
    return inside(row, col) && blocked_value(at(row, col), threshold, false);
  }

  /// World coordinates (metres) to continuous grid coordinates (cells): u along columns, v along rows.
  void world_to_grid(double x, double y, double& u, double& v) const {
    const double dx = x - origin.x, dy = y - origin.y;
    if (origin.theta == 0.0) {  // most maps: no trigonometry per call (same values: cos 0 = 1, sin 0 = 0)
      u = dx / resolution;
      v = dy / resolution;
      return;
    }
    const double c = std::cos(origin.theta), s = std::sin(origin.theta);
    u = (c * dx + s * dy) / resolution;
    v = (-s * dx + c * dy) / resolution;
  }
  void grid_to_world(double u, double v, double& x, double& y) const {
    if (origin.theta == 0.0) {
      x = origin.x + u * resolution;
      y = origin.y + v * resolution;
      return;
    }
    const double c = std::cos(origin.theta), s = std::sin(origin.theta);
    x = origin.x + (c * u - s * v) * resolution;
    y = origin.y + (s * u + c * v) * resolution;
  }
  /// The cell (row, col) holding the world point (x, y); it may lie outside the grid (inside() says).
  void world_to_cell(double x, double y, std::int64_t& row, std::int64_t& col) const {
    double u, v;
    world_to_grid(x, y, u, v);
    row = cell_index(v);
    col = cell_index(u);
  }
  /// World coordinates of the centre of cell (row, col).
  void cell_to_world(double row, double col, double& x, double& y) const { grid_to_world(col + 0.5, row + 0.5, x, y); }
  /// Whether the world point (x, y) lies on the map.
  bool contains(double x, double y) const {
    std::int64_t row, col;
    world_to_cell(x, y, row, col);
    return row >= 0 && col >= 0 && row < height && col < width;
  }
  /// Width and height of the map in metres.
  double width_m() const { return width * resolution; }
  double height_m() const { return height * resolution; }
};

/// Throws SchemaError naming `owner.field`: a size that is not positive or does not match the data,
/// a resolution that is not finite and > 0, an origin that is not finite.
void check_grid(const OccupancyGrid& grid, const std::string& owner);

}  // namespace vwg::geometry
