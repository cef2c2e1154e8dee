// The simulator's names for the shared geometry (vwg/geometry/): sim code, most of it written
// before the geometry library, says Pose2 and OccupancyGrid unqualified (over 200 places).
#pragma once

#include "vwg/geometry/occupancy_grid.hpp"
#include "vwg/geometry/pose.hpp"

namespace vwg::sim {

/// Height of the walls (and the ceiling) when a world gives none, metres: the cameras' and the 3D
/// overview's default.
inline constexpr double kDefaultWallHeight = 2.5;

using geometry::kFree;
using geometry::kObstacleThreshold;
using geometry::kOccupied;
using geometry::kUnknown;
using geometry::OccupancyGrid;
using geometry::Pose2;

}  // namespace vwg::sim
