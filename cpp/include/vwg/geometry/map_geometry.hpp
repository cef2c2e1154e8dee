// The size and placement of a map without its cells: what a robot's own map (an int16 blob) shares
// with the world's occupancy grid.
#pragma once

#include <cstddef>

#include "vwg/geometry/occupancy_grid.hpp"

namespace vwg::geometry {

struct MapGeometry {
  int width = 0, height = 0;
  double resolution = 0.05;
  Pose2 origin{};

  static MapGeometry of(const OccupancyGrid& g) { return MapGeometry{g.width, g.height, g.resolution, g.origin}; }
  OccupancyGrid frame() const;  ///< an empty grid of this geometry, for its coordinate functions
  /// The cell holding (x, y); false when it is outside the map.
  bool cell_of(double x, double y, int& row, int& col) const;
  /// The centre of cell (row, col) in world coordinates.
  void centre_of(int row, int col, double& x, double& y) const;
  std::size_t cells() const { return static_cast<std::size_t>(width) * height; }
};

}  // namespace vwg::geometry
