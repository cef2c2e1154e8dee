// Occupancy grids: the map every simulated sensor, the physics world, the renderers, the planners
// and the robots share.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "vwg/geometry/pose.hpp"

namespace vwg::geometry {

/// Values of an occupancy grid cell (nav_msgs/OccupancyGrid): -1 unknown, 0 free, 100 occupied;
/// maps loaded in "scale" mode hold values in between.
inline constexpr std::int8_t kUnknown = -1;
inline constexpr std::int8_t kFree = 0;
inline constexpr std::int8_t kOccupied = 100;

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
  bool blocked(int row, int col, int threshold = 50) const { return inside(row, col) && at(row, col) >= threshold; }

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
  /// Width and height of the map in metres.
  double width_m() const { return width * resolution; }
  double height_m() const { return height * resolution; }
};

}  // namespace vwg::geometry
