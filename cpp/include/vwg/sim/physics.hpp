// The physical world of the simulator: static walls from an occupancy grid and differential-drive
// robots as Box2D bodies, stepped at a fixed time step. Robots execute motion plans (turn, drive)
// under speed and acceleration limits; a seeded noise model perturbs motors and odometry.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "vwg/random.hpp"
#include "vwg/sim/grid.hpp"

namespace vwg::sim {

/// Speed and acceleration limits of a differential-drive robot.
struct RobotLimits {
  double max_speed = 0.5;       ///< m/s
  double max_turn_rate = 1.5;   ///< rad/s
  double max_accel = 1.0;       ///< m/s²
  double max_turn_accel = 4.0;  ///< rad/s²
};

struct RobotSettings {
  int id = 1;
  Pose2 start{};
  double radius = 0.18;  ///< m
  RobotLimits limits{};
};

/// The paper's "odometry errors" (§III.F test 3): standard deviations, 0 = exact.
struct NoiseModel {
  /// Motors: each commanded turn/drive is executed as amount·(1 + N(0, motors²)).
  double motors = 0.0;
  /// Odometry: the pose estimate drifts from the true pose; per step, the measured increment of
  /// distance ds and angle da get N(0, odometry²·|ds|) and N(0, odometry²·|da|) (a random walk,
  /// so the error grows with the square root of the distance travelled).
  double odometry = 0.0;
};

struct PhysicsSettings {
  double step = 0.01;  ///< fixed time step of Box2D, seconds
  int velocity_iterations = 8;
  int position_iterations = 3;
  int obstacle_threshold = 50;  ///< grid values >= this are walls
  bool walls_at_border = true;  ///< a wall around the map, so robots cannot leave it
  NoiseModel noise{};
  std::uint64_t seed = 0;
};

/// One step of a motion plan, in the robot's own frame.
struct MotionStep {
  enum Kind : std::uint8_t { Turn, Drive } kind;
  double amount;  ///< radians (counter-clockwise) or metres (forward; negative backwards)
};

struct RobotState {
  int id = 0;
  double radius = 0.0;
  Pose2 pose{};      ///< true pose (what the simulator knows)
  Pose2 odometry{};  ///< the robot's own estimate (equal to pose without odometry noise)
  double speed = 0.0;      ///< m/s along the heading
  double turn_rate = 0.0;  ///< rad/s
  bool busy = false;       ///< executing a motion plan
  std::uint64_t commands = 0;  ///< motion plans received so far (a robot can tell its last one arrived)
  std::uint64_t collisions = 0;
  double travelled = 0.0;  ///< metres driven (true)
};

/// A robot touched a wall or another robot (reported when the contact begins), or gave up a drive
/// because it pushed against one without moving.
struct Collision {
  int robot = 0;
  int other = 0;  ///< id of the other robot, 0 for a wall
  Pose2 pose{};
  double time = 0.0;
};

class PhysicsWorld {
 public:
  /// Throws vwg::SchemaError for bad settings (a robot outside the map, overlapping a wall or
  /// another robot, duplicate ids, non-finite or non-positive limits).
  PhysicsWorld(const OccupancyGrid& grid, std::span<const RobotSettings> robots, PhysicsSettings settings);
  ~PhysicsWorld();
  PhysicsWorld(const PhysicsWorld&) = delete;
  PhysicsWorld& operator=(const PhysicsWorld&) = delete;

  /// Replace the robot's current plan with `plan` (the latest command wins; an empty plan stops it).
  void command(int robot, std::vector<MotionStep> plan);
  /// Step the world for `seconds` (a whole number of fixed steps; the remainder carries over).
  void advance(double seconds);

  const RobotState& robot(int id) const;
  std::span<const RobotState> robots() const { return states_; }
  /// Collisions since the last call.
  std::vector<Collision> take_collisions();
  double time() const { return time_; }
  const OccupancyGrid& grid() const { return grid_; }
  /// How many rectangles the walls were merged into (one Box2D fixture each).
  std::size_t wall_shapes() const { return wall_shapes_; }

  /// Rectangles [row0, row1) × [col0, col1) of blocked cells covering every blocked cell once:
  /// maximal horizontal runs grown upwards while the rows below agree (a greedy cover).
  struct CellRect {
    int row0, col0, row1, col1;
  };
  static std::vector<CellRect> merge_walls(const OccupancyGrid& grid, int threshold);

 private:
  struct Robot;
  class Contacts;
  void step_robot(Robot& r, double dt);
  void start_step(Robot& r);
  Robot& find(int id);

  OccupancyGrid grid_;
  PhysicsSettings settings_;
  struct Box2D;
  std::unique_ptr<Box2D> box2d_;
  std::vector<Robot> robots_;
  std::vector<RobotState> states_;
  std::vector<Collision> collisions_;
  std::unique_ptr<Contacts> contacts_;
  double time_ = 0.0;
  double pending_ = 0.0;
  std::size_t wall_shapes_ = 0;
};

}  // namespace vwg::sim
