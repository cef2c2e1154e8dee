// Where the frame meets a robot, simulated or real (DESIGN.md, "The platform"). The motion backend
// (φ of Rotate<a>(Move<d>(Robot<id>))) and the feedback generators (odometry, collisions) know
// this interface only; the Box2D simulator implements it, and so can a real-robot link (in C++ or
// in Python: the bindings let a Python class implement it). Switching platform is one setting; the
// world string does not change (paper §III.F, test 3).
#pragma once

#include <concepts>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "vwg/geometry/pose.hpp"
#include "vwg/state.hpp"

namespace vwg::platform {

using geometry::Pose2;

/// Speed and acceleration limits of a differential-drive robot.
struct RobotLimits {
  double max_speed = 0.5;       ///< m/s
  double max_turn_rate = 1.5;   ///< rad/s
  double max_accel = 1.0;       ///< m/s²
  double max_turn_accel = 4.0;  ///< rad/s²
};

/// The radius of a robot none was given for (a TurtleBot-sized disc), metres: RobotSettings' default,
/// and so that of every struct that describes a robot (ARobotConfig, DecisionInput, RobotShape).
inline constexpr double kDefaultRobotRadius = 0.18;

/// A robot as the world file describes it: id, start pose, size, limits and the sensors it carries
/// (by registered name). The defaults here are the only ones (bindings and loaders take them).
struct RobotSettings {
  int id = 1;
  Pose2 start{};
  double radius = kDefaultRobotRadius;  ///< m
  RobotLimits limits{};
  std::vector<std::string> sensors{"laser", "camera"};
};

/// Each field with its name and meaning (the limits flat, as world files write them).
template <class S, class F>
  requires std::same_as<std::remove_const_t<S>, RobotSettings>
void visit_settings(S& s, F&& field) {
  field("id", s.id, "the robot's id, >= 1: events are addressed to it");
  field("start", s.start, "start pose (x, y, yaw): metres, metres, radians");
  field("radius", s.radius, "metres");
  field("max_speed", s.limits.max_speed, "m/s");
  field("max_turn_rate", s.limits.max_turn_rate, "rad/s");
  field("max_accel", s.limits.max_accel, "m/s²");
  field("max_turn_accel", s.limits.max_turn_accel, "rad/s²");
  field("sensors", s.sensors, "the sensors it carries, by registered name (laser, kinect, camera, ...)");
}

/// The largest map coordinate (metres) and angle (radians) a platform takes: Box2D keeps them as float
/// and aborts the process on what a float cannot hold, so they are refused where they are read.
inline constexpr double kMaxCoordinate = 1e6;
inline constexpr double kMaxAngle = 1e3;

/// Throws SchemaError naming `owner.field` for an id < 1, a start that is not finite or beyond
/// kMaxCoordinate / kMaxAngle, a radius (<= 100 m) or limit that is not finite, > 0 and within its
/// bound, or a sensor named twice or empty.
void check_settings(const RobotSettings& robot, const std::string& owner);

/// One step of a motion command, in the robot's own frame: turn by an angle, drive a distance, or steer (hold a
/// speed and a turn rate, reached within the acceleration limits, until the next command: a local planner's
/// velocity, such as reciprocal avoidance's, given every frame).
struct MotionStep {
  enum Kind : std::uint8_t { Turn, Drive, Steer } kind;
  double amount;      ///< radians (counter-clockwise), metres (forward; negative backwards), or m/s for Steer
  double rate = 0.0;  ///< Steer: rad/s, counter-clockwise
};

/// What a platform knows of one robot after its last step.
struct RobotState {
  int id = 0;
  double radius = 0.0;
  Pose2 pose{};      ///< the platform's best pose: the truth in a simulator, start ⊕ odometry on a real robot
  Pose2 odometry{};  ///< the robot's own estimate (equal to pose without odometry noise)
  double speed = 0.0;      ///< m/s along the heading
  double turn_rate = 0.0;  ///< rad/s
  bool busy = false;       ///< executing a motion command
  std::uint64_t commands = 0;  ///< motion commands received so far (acknowledgements: a robot can tell its last one arrived)
  std::uint64_t collisions = 0;
  double travelled = 0.0;  ///< metres driven
};

/// A robot touched a wall or another robot (reported when the contact begins), or gave up a drive
/// because it pushed against one without moving.
struct Collision {
  int robot = 0;
  int other = 0;  ///< id of the other robot, 0 for a wall
  Pose2 pose{};
  double time = 0.0;
};

class RobotPlatform {
 public:
  virtual ~RobotPlatform() = default;
  /// Add a robot (a body in a simulator, a link's robot on a real one). Throws vwg::SchemaError for
  /// bad settings or an id in use.
  virtual void add_robot(const RobotSettings& robot) = 0;
  /// Remove a robot: it is stopped and no longer reported. Throws vwg::SchemaError for an unknown id.
  virtual void remove_robot(int id) = 0;
  /// Replace robot `id`'s current command by `steps` (the latest command wins; none stops it).
  virtual void command(int id, std::vector<MotionStep> steps) = 0;
  /// Let `seconds` pass on the platform: a simulator steps its physics, a real robot's link runs
  /// its control loop until its clock has advanced as much.
  virtual void advance(double seconds) = 0;
  /// Every robot's state, by increasing id.
  virtual const std::vector<RobotState>& robots() const = 0;
  /// One robot's state; throws vwg::SchemaError for an unknown id.
  virtual const RobotState& robot(int id) const;
  /// One robot's state, or null when the platform has no robot of that id: a robot's own generators
  /// (its sensors, its localization) ask this each frame, and emit nothing for a robot a λ took out of the
  /// string (PlatformSync removed its body).
  virtual const RobotState* find_robot(int id) const;
  /// The contacts since the last call.
  virtual std::vector<Collision> take_collisions() = 0;
  /// The platform's clock, seconds since it started.
  virtual double time() const = 0;
  virtual std::string name() const = 0;
  /// Everything that decides what the platform does next (bodies, contacts, clocks, motion
  /// followers, noise), for a saved run (vwg/state.hpp). The default refuses, naming the platform: a
  /// real robot's cannot be saved.
  virtual void save_state(StateWriter& out) const;
  /// Back to what save_state() wrote, on a platform made as the saved one was (same robots, same
  /// settings) and not yet stepped.
  virtual void load_state(StateReader& in);
};

}  // namespace vwg::platform
