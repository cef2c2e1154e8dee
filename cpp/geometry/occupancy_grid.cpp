#include "vwg/geometry/occupancy_grid.hpp"

#include "vwg/error.hpp"
#include "vwg/text.hpp"

namespace vwg::geometry {

void check_grid(const OccupancyGrid& grid, const std::string& owner) {
  if (grid.width <= 0 || grid.height <= 0) {
    throw SchemaError(owner + ".data", "expected a non-empty grid, got " + std::to_string(grid.height) + " × " +
                                           std::to_string(grid.width) + " cells");
  }
  if (grid.data.size() != static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height)) {
    throw SchemaError(owner + ".data", "a grid of " + std::to_string(grid.height) + " × " + std::to_string(grid.width) +
                                           " cells holds " + std::to_string(grid.data.size()) + " values");
  }
  if (!std::isfinite(grid.resolution) || grid.resolution <= 0) {
    throw SchemaError(owner + ".resolution", "expected a finite number > 0, got " + format_real(grid.resolution));
  }
  if (!std::isfinite(grid.origin.x) || !std::isfinite(grid.origin.y) || !std::isfinite(grid.origin.theta)) {
    throw SchemaError(owner + ".origin", "expected three finite numbers (x, y, yaw), got (" + format_real(grid.origin.x) +
                                             ", " + format_real(grid.origin.y) + ", " + format_real(grid.origin.theta) + ")");
  }
}

}  // namespace vwg::geometry
