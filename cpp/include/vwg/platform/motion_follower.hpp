// Following a motion plan (turn and drive steps, the robot's own frame) on a pose: a trapezoidal
// speed profile within the robot's limits, recomputed at every tick from where the pose says the
// robot is, so a step ends when the pose says it is done, not on a timer. The simulator runs it
// on the true pose at every physics step; a real robot's link on its odometry at every control
// tick. One follower for both is what makes the same world string move both robots alike (paper
// §III.F, test 3): given the same poses, both send the same velocities.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include "vwg/geometry/pose.hpp"
#include "vwg/platform/platform.hpp"

namespace vwg::platform {

/// A velocity command: m/s along the heading, rad/s counter-clockwise.
struct Velocity {
  double speed = 0.0;
  double turn_rate = 0.0;
};

class MotionFollower {
 public:
  /// `tolerance`: a step whose last tick meant to land on its end is done when the pose is within
  /// this distance (m) or angle (rad) of it; otherwise it goes on from where the robot is.
  explicit MotionFollower(RobotLimits limits, double tolerance = kDefaultTolerance);
  static constexpr double kDefaultTolerance = 0.01;  ///< m or rad

  /// Replace the plan (the latest command wins; an empty one brings the robot to rest). A Steer step holds its
  /// velocity, clamped to the limits, from when it is reached until the next command. Throws vwg::SchemaError
  /// for a non-finite amount or rate.
  void command(const std::vector<MotionStep>& steps);
  /// The velocity to hold for the next `dt` seconds, the robot being at `pose` now.
  Velocity tick(const geometry::Pose2& pose, double dt);
  /// After the platform moved: a step whose end the last tick meant to reach is done if `pose`
  /// says so (tick() does this too; calling it right after a step keeps busy() exact).
  void settle(const geometry::Pose2& pose);
  /// Drop the plan and command no motion at once (an emergency stop, not a braked one).
  void stop();
  /// Command no motion at once but keep the plan: it goes on from rest at the next tick (a robot
  /// held while its odometry is silent).
  void halt() { velocity_ = {}; lands_ = false; }

  bool busy() const { return active_ || !plan_.empty(); }
  /// The step under way is a drive, or a held speed is not zero (false when idle or turning).
  bool driving() const { return active_ ? current_.kind == MotionStep::Drive : hold_.speed != 0.0; }
  Velocity velocity() const { return velocity_; }
  const RobotLimits& limits() const { return limits_; }

 private:
  double remaining(const geometry::Pose2& pose);

  RobotLimits limits_;
  double tolerance_;
  std::deque<MotionStep> plan_;
  bool active_ = false;  // a step of the plan is under way
  MotionStep current_{MotionStep::Turn, 0.0};
  geometry::Pose2 origin_{};  // where the current step began
  double turned_ = 0.0;       // the current turn's progress, unwrapped (a turn may pass ±π)
  double last_theta_ = 0.0;
  bool lands_ = false;  // the last tick's velocity reaches the step's end within its dt
  Velocity hold_{};     // what a Steer step asked for: approached when no step is under way (else rest)
  Velocity velocity_{};
};

/// `pose` at the resolution of the simulator's floats: x and y rounded to float, the angle wrapped
/// into [-π, π] and rounded to float. Every platform reports poses so, which lets a pose carried
/// through a link's messages (JSON numbers, quaternions, a frame transform) come back bit for bit.
geometry::Pose2 quantize_pose(const geometry::Pose2& pose);

}  // namespace vwg::platform
