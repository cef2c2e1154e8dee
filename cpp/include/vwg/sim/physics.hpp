// The physical world of the simulator: static walls from an occupancy grid and differential-drive
// robots as Box2D bodies, stepped at a fixed time step. Robots follow motion plans (turn, drive)
// on their true pose with the platform's MotionFollower, under speed and acceleration limits, or
// hold velocities given by drive(); a seeded noise model perturbs motors and odometry.
#pragma once

#include <concepts>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "vwg/random.hpp"
#include "vwg/platform/motion_follower.hpp"
#include "vwg/platform/platform.hpp"
#include "vwg/detail/disc_index.hpp"
#include "vwg/sim/grid.hpp"

class b2Body;

namespace vwg::sim {

// The robot vocabulary is the platform's (vwg/platform/platform.hpp): the simulator is one platform.
using platform::Collision;
using platform::MotionStep;
using platform::RobotLimits;
using platform::RobotSettings;
using platform::RobotState;

/// The paper's "odometry errors" (§III.F test 3): standard deviations, 0 = exact.
struct NoiseModel {
  /// Motors: each commanded turn/drive is executed as amount·(1 + N(0, motors²)).
  double motors = 0.0;
  /// Odometry: the pose estimate drifts from the true pose; per step, the measured increment of
  /// distance ds and angle da get N(0, odometry²·|ds|) and N(0, odometry²·|da|) (a random walk,
  /// so the error grows with the square root of the distance travelled).
  double odometry = 0.0;
};

template <class S, class F>
  requires std::same_as<std::remove_const_t<S>, NoiseModel>
void visit_settings(S& s, F&& field) {
  field("motors", s.motors, "relative standard deviation of each commanded turn and drive");
  field("odometry", s.odometry, "standard deviation of the odometry's drift, per metre and per radian");
}

/// Throws SchemaError naming `owner.field` for a standard deviation that is not finite and >= 0.
void check_settings(const NoiseModel& noise, const std::string& owner);

struct PhysicsSettings {
  double step = 0.01;  ///< fixed time step of Box2D, seconds
  int velocity_iterations = 8;
  int position_iterations = 3;
  int obstacle_threshold = kObstacleThreshold;  ///< grid values >= this are walls
  bool walls_at_border = true;  ///< a wall around the map, so robots cannot leave it
  NoiseModel noise{};
  std::uint64_t seed = 0;
};

template <class S, class F>
  requires std::same_as<std::remove_const_t<S>, PhysicsSettings>
void visit_settings(S& s, F&& field) {
  field("step", s.step, "fixed time step of Box2D, seconds");
  field("velocity_iterations", s.velocity_iterations, "Box2D's velocity iterations per step");
  field("position_iterations", s.position_iterations, "Box2D's position iterations per step");
  field("obstacle_threshold", s.obstacle_threshold, "grid values >= this are walls");
  field("walls_at_border", s.walls_at_border, "a wall around the map, so robots cannot leave it");
  field("noise", s.noise, "motor and odometry noise");
  field("seed", s.seed, "seed of the noise");
}

/// Throws SchemaError naming `owner.field` for a step that is not finite and > 0 (at most 1 s),
/// iterations outside 1..1000, a threshold outside 1..100, or bad noise.
void check_settings(const PhysicsSettings& settings, const std::string& owner);

/// The Box2D simulator as a RobotPlatform.
class PhysicsWorld final : public platform::RobotPlatform {
 public:
  /// Throws vwg::SchemaError for bad settings (a robot outside the map, overlapping a wall or
  /// another robot, duplicate ids, non-finite or non-positive limits).
  PhysicsWorld(const OccupancyGrid& grid, std::span<const RobotSettings> robots, PhysicsSettings settings);
  ~PhysicsWorld();
  PhysicsWorld(const PhysicsWorld&) = delete;
  PhysicsWorld& operator=(const PhysicsWorld&) = delete;

  /// A robot's body; throws SchemaError like the constructor (and for an id in use).
  void add_robot(const RobotSettings& robot) override;
  /// The robot's body leaves the world.
  void remove_robot(int id) override;
  /// Replace the robot's current plan with `plan` (the latest command wins; an empty plan stops it).
  void command(int robot, std::vector<MotionStep> plan) override;
  /// Hold robot `robot` at these velocities (m/s, rad/s) from now on, as a base driven by velocity
  /// commands is (a fake robot behind a link); its plan, if any, is dropped. command() ends it.
  void drive(int robot, double speed, double turn_rate);
  /// Step the world for `seconds` (a whole number of fixed steps; the remainder carries over).
  void advance(double seconds) override;
  /// A person (vwg/sim/people.hpp): a kinematic disc put at (x, y) and moving at (vx, vy) until told again,
  /// made at its first call with that radius. Robots touch it (a collision whose `other` is −id) and the
  /// lasers and cameras see it; it does not stop at walls (people steer clear of them themselves). Throws
  /// SchemaError for an id < 1, a position outside kMaxCoordinate, a radius not in (0, 10] or values that are
  /// not finite.
  void set_person(int id, double x, double y, double vx, double vy, double radius);
  struct Person {
    int id = 0;
    double x = 0.0, y = 0.0, vx = 0.0, vy = 0.0, radius = 0.0;
  };
  /// The people, in the order they were first set.
  const std::vector<Person>& people() const { return people_; }

  const RobotState& robot(int id) const override;
  const RobotState* find_robot(int id) const override;
  const std::vector<RobotState>& robots() const override { return states_; }
  /// Where each robot's disc is, in the order of robots(), then each person's (id −person): what the lasers
  /// read.
  using Disc = sim::Disc;
  const std::vector<Disc>& discs() const { return discs_; }
  /// The discs by squares of the floor, kept with them: a laser looks only at the discs near it.
  const DiscIndex& disc_index() const { return disc_index_; }
  /// Collisions since the last call.
  std::vector<Collision> take_collisions() override;
  double time() const override { return time_; }
  std::string name() const override { return "sim"; }
  const OccupancyGrid& grid() const { return grid_; }
  /// The simulator's state is what was done to it since it was made: every robot added or
  /// removed, every command, drive and advance, every take of the collisions, in order (its
  /// journal). Box2D 2.4 keeps its broad phase (a tree whose shape and proxy numbers follow the
  /// bodies' history) and its contacts' order private, and both decide the next steps' bits; so a
  /// saved simulator is its journal and the fingerprint of what it was made from, and loading runs
  /// the journal again on a simulator made the same way, without sensing or deciding.
  void save_state(StateWriter& out) const override;
  /// Throws SchemaError("platform sim") for a state of another map, settings or robots, or one this
  /// simulator's own journal is not the beginning of.
  void load_state(StateReader& in) override;
  /// Bytes of the journal so far (what a saved state holds beside its fingerprint).
  std::size_t journal_bytes() const { return journal_.bytes().size(); }
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
  /// add_robot without rebuilding the disc index (the constructor rebuilds it once for all).
  void add_body(const RobotSettings& robot);
  void step_robot(Robot& r, const RobotState& state, double dt);
  Robot& find(int id);
  std::size_t index_of(int id) const;

  OccupancyGrid grid_;
  PhysicsSettings settings_;
  struct Box2D;
  std::unique_ptr<Box2D> box2d_;
  std::vector<Robot> robots_;
  std::vector<RobotState> states_;
  std::vector<Disc> discs_;                    ///< discs_[i]: states_[i]'s pose and radius, set with it; then people_'s
  std::vector<Person> people_;
  std::vector<b2Body*> person_bodies_;         ///< person_bodies_[k]: people_[k]'s, owned by the b2World
  DiscIndex disc_index_;                       ///< of discs_, rebuilt whenever they change
  std::unordered_map<int, std::size_t> index_;  ///< robot id -> i in robots_, states_ and discs_
  std::vector<Collision> collisions_;
  std::unique_ptr<Contacts> contacts_;
  double time_ = 0.0;
  double pending_ = 0.0;
  std::size_t wall_shapes_ = 0;
  /// What it was made from (map, settings, robots), so a state is loaded only where it was saved.
  std::uint64_t fingerprint_ = 0;
  StateWriter journal_;  // see save_state()
};

}  // namespace vwg::sim
