#include "vwg/geometry/map_geometry.hpp"

namespace vwg::geometry {

OccupancyGrid MapGeometry::frame() const {
  OccupancyGrid g;
  g.width = width;
  g.height = height;
  g.resolution = resolution;
  g.origin = origin;
  return g;
}

bool MapGeometry::cell_of(double x, double y, int& row, int& col) const {
  double u, v;
  frame().world_to_grid(x, y, u, v);
  if (!(u >= 0 && v >= 0 && u < width && v < height)) return false;
  col = static_cast<int>(u);
  row = static_cast<int>(v);
  return true;
}

void MapGeometry::centre_of(int row, int col, double& x, double& y) const { frame().grid_to_world(col + 0.5, row + 0.5, x, y); }

}  // namespace vwg::geometry
