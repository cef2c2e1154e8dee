// Where segment_clear (vwg/robot/robot_map.hpp) looks on a robot's map: the one conversion of a segment in
// metres to cell units, for segment_clear itself and for a reader that follows the map's changes (ClearPathMemo).
// Private to vwg's libraries (beside their sources, under cpp/): not installed.
#pragma once

#include "geometry/clearance.hpp"
#include "vwg/geometry/map_geometry.hpp"

namespace vwg::robot {

/// A segment and a disc's radius in cell units (columns u, rows v), as segment_clear tests them.
struct SegmentInCells {
  double u0, v0, u1, v1, radius;
};
SegmentInCells segment_in_cells(const geometry::MapGeometry& g, double x0, double y0, double x1, double y1, double radius);

/// The cells segment_clear(map, g, x0, y0, x1, y1, radius) looks at: a change elsewhere cannot change its answer.
inline geometry::CellWindow segment_clear_window(const geometry::MapGeometry& g, double x0, double y0, double x1, double y1,
                                                 double radius) {
  const SegmentInCells s = segment_in_cells(g, x0, y0, x1, y1, radius);
  return geometry::segment_window(s.u0, s.v0, s.u1, s.v1, s.radius, g.height, g.width);
}

}  // namespace vwg::robot
