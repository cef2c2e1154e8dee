// Sampling-based planners of OMPL (RRTConnect, RRT*, PRM, ...) for a disc-shaped robot on an
// occupancy grid: poses (x, y, yaw) in the map's world frame, collisions tested exactly against
// the blocked cells. OMPL stays inside the .cpp: including this header needs no OMPL headers.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "vwg/geometry/clearance_field.hpp"
#include "vwg/plan/grid_graph.hpp"
#include "vwg/geometry/occupancy_grid.hpp"
#include "vwg/geometry/pose.hpp"

namespace vwg::plan {

/// How to plan.
struct OmplOptions {
  /// An OMPL geometric planner by name (see OmplGridPlanner::planner_names()).
  std::string planner = "RRTConnect";
  /// Seconds the planner may run (0: no time limit, `iterations` alone bounds it). Anytime planners
  /// (RRT*, PRM, ...) use all of it to improve the path. A time limit makes plans depend on the
  /// machine's speed and load: a reproducible run uses iterations alone.
  double time_limit = 1.0;
  /// Seeds OMPL's random numbers (ompl::RNG::setSeed) before every plan, so a plan is reproducible:
  /// same map, poses, options and seed, same path, for planners that are single-threaded and stop by
  /// themselves (RRTConnect, RRT, KPIECE1, ... stop at their first solution; with `iterations`
  /// set, RRT* and the like too). PRM is not reproducible: it grows its roadmap in time slices and
  /// checks for solutions on a second thread.
  std::uint32_t seed = 0;
  /// Stop after this many planner iterations (0: only the time limit). With a seed and no time
  /// limit, single-threaded planners (all but PRM and PRMstar) give the same plan everywhere.
  unsigned iterations = 0;
  /// Shorten the path found (OMPL's PathSimplifier: shortcuts and vertex removal, no time limit).
  bool simplify = true;
  /// Metres between the waypoints returned: straight segments are subdivided. Unset: one cell
  /// (the map's resolution); 0: the planner's vertices only.
  std::optional<double> spacing;
  /// Let OMPL print its informational messages (it otherwise prints only warnings and errors).
  bool verbose = false;
};

/// The outcome of a plan. On failure: no waypoints, infinite length, and `status` says why.
struct OmplPlan {
  bool solved = false;
  /// "exact solution", or why not: "timeout" (no path found in time), "approximate solution"
  /// (the planner got only near the goal), "invalid goal: ..." (the goal pose is in collision or
  /// off the map), or OMPL's own status text.
  std::string status;
  std::vector<geometry::Pose2> waypoints;  ///< from the start pose to the goal pose, in the world frame
  double length = std::numeric_limits<double>::infinity();  ///< metres travelled in x-y (yaw not counted)
  double plan_time = 0.0;      ///< seconds spent by the planner
  double simplify_time = 0.0;  ///< seconds spent shortening the path
  std::string planner;
};

/// A disc-shaped robot on a map, and planning for it with OMPL in SE(2).
///
/// The collision test is exact: a pose is valid when the disc of `robot_radius` around (x, y) stays
/// strictly away from every blocked cell and inside the map; a motion between two poses (a straight
/// line in x-y, as OMPL's SE(2) interpolates) is valid when every pose along it is, which is tested
/// without sampling (see geometry::ClearanceField::segment_clear), so paths never cross or graze an obstacle.
/// Yaw is planned (start and goal headings are reached) but does not affect collisions.
class OmplGridPlanner {
 public:
  /// `grid`: blocked cells with row 0 the bottom row (smallest y), as OccupancyGrid; `resolution`
  /// metres per cell; `origin` the pose of the lower-left corner of cell (0, 0) in the world frame.
  /// Throws SchemaError("resolution"/"robot_radius"/"grid") for non-positive or non-finite values
  /// or an empty grid.
  OmplGridPlanner(BlockedGrid grid, double resolution, geometry::Pose2 origin, double robot_radius);
  /// The obstacles of an occupancy grid (see BlockedGrid::from_occupancy) with its geometry.
  static OmplGridPlanner from_occupancy(const geometry::OccupancyGrid& grid, double robot_radius, int threshold = geometry::kObstacleThreshold,
                                        bool unknown_blocked = true);

  /// Plan from `start` to `goal`. Throws SchemaError("start_pose") when the start is off the map,
  /// not finite or in collision, SchemaError("planner"/"time_limit"/...) for bad options; an
  /// invalid goal is a failed plan ("invalid goal: ..."), like a blocked goal cell for A*.
  /// Plans are serialised process-wide (OMPL's random seed is global); the caller's thread blocks.
  OmplPlan plan(const geometry::Pose2& start, const geometry::Pose2& goal, const OmplOptions& options = {}) const;

  /// Whether the robot fits at (x, y).
  bool valid(double x, double y) const;
  /// Whether the robot can move in a straight line from (x0, y0) to (x1, y1).
  bool motion_valid(double x0, double y0, double x1, double y1) const;
  /// Metres from (x, y) to the nearest obstacle (or map edge), up to `cap` metres.
  double clearance(double x, double y, double cap = kDefaultClearanceCap) const;
  static constexpr double kDefaultClearanceCap = 1.0;  ///< metres

  /// World (metres) to continuous grid coordinates (cells), as OccupancyGrid::world_to_grid.
  void world_to_grid(double x, double y, double& u, double& v) const;
  void grid_to_world(double u, double v, double& x, double& y) const;

  double resolution() const { return resolution_; }
  const geometry::Pose2& origin() const { return origin_; }
  double robot_radius() const { return robot_radius_; }
  const geometry::ClearanceField& field() const { return field_; }

  /// The planner names `plan` accepts.
  static std::vector<std::string> planner_names();

 private:
  geometry::ClearanceField field_;
  double resolution_;
  geometry::Pose2 origin_;
  double robot_radius_;
  double radius_cells_;
};

/// One plan on a map (builds the OmplGridPlanner, whose distance transform costs a pass over the map).
OmplPlan plan_ompl(const BlockedGrid& grid, double resolution, const geometry::Pose2& origin, const geometry::Pose2& start,
                   const geometry::Pose2& goal, double robot_radius, const OmplOptions& options = {});

}  // namespace vwg::plan
