// The geometry library in vwg._core: clearance and inflation of occupancy grids, so that
// vwg.maps.OccupancyGrid answers with the same code as the robots and planners.
#include <cstdint>

#include "common.hpp"
#include "sim_convert.hpp"
#include "geometry/clearance.hpp"
#include "geometry/inflate.hpp"

namespace vwg::bindings {

void init_geometry(py::module_& m) {
  m.def(
      "grid_clearance",
      [](MapArg grid, double x, double y, double limit, int threshold, bool unknown) {
        return geometry::clearance(grid_from_python(grid), x, y, limit, threshold, unknown);
      },
      py::arg("grid"), py::arg("x"), py::arg("y"), py::arg("limit"), py::arg("threshold") = 50, py::arg("unknown") = true,
      "Distance (m) from the world point (x, y) to the nearest cell of value >= threshold (and unknown cells and "
      "everything off the grid when `unknown`), capped at `limit`; 0 inside one.");
  m.def(
      "grid_inflate",
      [](MapArg grid, double radius, int threshold, bool unknown) {
        const geometry::OccupancyGrid g = grid_from_python(grid);
        const geometry::BlockedGrid out =
            geometry::inflate(geometry::BlockedGrid::from_occupancy(g, threshold, unknown), radius / g.resolution, unknown);
        py::array_t<bool> mask({g.height, g.width});
        auto cells = mask.mutable_unchecked<2>();
        for (int r = 0; r < g.height; ++r) {
          for (int c = 0; c < g.width; ++c) cells(r, c) = out.blocked({r, c});
        }
        return mask;
      },
      py::arg("grid"), py::arg("radius"), py::arg("threshold") = 50, py::arg("unknown") = true,
      "Boolean mask of the cells whose centre is within `radius` metres (inclusive) of a cell of value >= threshold "
      "(and of unknown cells and the grid's edge when `unknown`): where a disc robot's centre may not be.");
}

}  // namespace vwg::bindings
