// A robot of the case study from C++: its own map of a small world (a wall across a room, with a
// gap), an obstacle its sensors report in the gap, and the A* decider's plan around the wall.
// Exits non-zero unless the plan is the one worked out by hand below, so building and running this
// example tests the installed vwg::robot (and, through it, vwg::geometry and vwg::plan).
#include <cmath>
#include <cstdio>
#include <memory>

#include <vwg/geometry/map_geometry.hpp>
#include <vwg/geometry/occupancy_grid.hpp>
#include <vwg/robot/planners.hpp>
#include <vwg/robot/registries.hpp>
#include <vwg/robot/robot_map.hpp>

namespace {

int fail(const char* what) {
  std::fprintf(stderr, "robot_planner: %s\n", what);
  return 1;
}

}  // namespace

int main() {
  // 20 × 10 cells of 0.1 m: a wall down column 10 with gaps at rows 1-2 (bottom) and 7-8 (top).
  vwg::geometry::OccupancyGrid world;
  world.width = 20;
  world.height = 10;
  world.resolution = 0.1;
  world.data.assign(200, vwg::geometry::kFree);
  for (int row = 0; row < 10; ++row) {
    if (row != 1 && row != 2 && row != 7 && row != 8) world.data[static_cast<std::size_t>(row) * 20 + 10] = vwg::geometry::kOccupied;
  }
  const auto geometry = vwg::geometry::MapGeometry::of(world);
  auto map = vwg::robot::make_robot_map(world, /*knows_map=*/true);

  // The laser reports something in the bottom gap (x 1.05, y 0.15 and 0.25): the robot marks it.
  {
    vwg::robot::MapEdit edit(*map);
    if (!vwg::robot::mark_obstacle(edit, geometry, 1.05, 0.15) || !vwg::robot::mark_obstacle(edit, geometry, 1.05, 0.25)) {
      return fail("the reported obstacle did not change the map");
    }
  }

  // From the bottom left to the bottom right, a robot of radius 0.04 m (the 0.2 m gaps stay open).
  vwg::robot::DecisionInput in;
  in.map = map;
  in.geometry = &geometry;
  in.pose = {0.25, 0.15, 0.0};
  in.goal_x = 1.75;
  in.goal_y = 0.15;
  in.radius = 0.04;
  in.step_length = 5.0;
  // The decider by its registered name, as a world file or `--planner` names it.
  const std::shared_ptr<vwg::robot::Decider> planner = vwg::robot::deciders().create("astar");
  vwg::robot::Decider& astar = *planner;
  const vwg::robot::Decision d = astar.decide(in);
  if (d.kind != vwg::robot::Decision::Kind::Move) return fail("A* found no path");
  const auto& p = d.path;
  if (p.size() < 4) return fail("the plan has fewer than two points");

  // The bottom gap is blocked now, so the plan goes through the top gap (rows 7-8: y 0.7-0.9).
  double top = 0.0, length = 0.0;
  for (std::size_t i = 0; i + 1 < p.size(); i += 2) {
    top = std::fmax(top, p[i + 1]);
    if (i + 3 < p.size()) length += std::hypot(p[i + 2] - p[i], p[i + 3] - p[i + 1]);
  }
  const double end_x = p[p.size() - 2], end_y = p[p.size() - 1];
  std::printf("robot_planner: %s plan of %zu points, %.2f m, up to y = %.2f m, ends at (%.2f, %.2f); first move: turn %.3f rad, %.2f m\n",
              astar.name().c_str(), p.size() / 2, length, top, end_x, end_y, d.turn, d.distance);
  if (!(top > 0.7 && top < 0.9)) return fail("the plan does not pass through the top gap");
  if (std::hypot(end_x - 1.75, end_y - 0.15) > 0.1) return fail("the plan does not end at the goal");
  // Up to the top gap and down again: more than 1.8 m (the bottom gap was 1.5 m), not a wander.
  if (!(length > 1.8 && length < 2.6)) return fail("the plan's length is not that of the detour");
  if (!vwg::robot::path_clear(in, p)) return fail("the plan is not clear of the map's obstacles");
  return 0;
}
