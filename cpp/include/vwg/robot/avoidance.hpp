// Reciprocal avoidance in the robots: the layer between a robot's decision and its motion (the paper's robot
// "uses the sensors to detect and avoid obstacles"). In the model it is two parts:
//
//   gNeighbours   a generator a robot: the robots and people its own laser sees (platform::NeighbourTracker on
//                 its scans, not the simulator's truth), as eNeighbour<x, y, vx, vy, radius> events addressed
//                 to it, in its own frame (x ahead, y to the left), moved on to the frame's time
//   λ(eDecide)    of a robot with `avoid` set: every frame, the decider's next step is the preferred velocity,
//                 ORCA (vwg/robot/orca.hpp) makes it safe for the neighbours of this frame, and steer() turns
//                 it into a speed and a turn rate within the robot's limits, shown as
//                 Velocity<speed, turn_rate>(Robot<id>) (held by the platform until the next frame's)
#pragma once

#include <concepts>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <type_traits>

#include "vwg/alphabet.hpp"
#include "vwg/generator.hpp"
#include "vwg/geometry/pose.hpp"
#include "vwg/platform/motion_follower.hpp"
#include "vwg/platform/neighbours.hpp"
#include "vwg/platform/platform.hpp"
#include "vwg/platform/scan_source.hpp"
#include "vwg/robot/orca.hpp"

namespace vwg::robot {

struct AvoidanceSettings {
  double horizon = 2.0;        ///< seconds: the velocity keeps the robot clear of its neighbours this long
  double margin = 0.1;         ///< metres added to the robot's radius (a differential drive follows a velocity late)
  double heading_time = 0.4;   ///< seconds: the turn rate is the heading error over this (within the limit)
  double step = 0.1;           ///< seconds within which robots that already overlap part
  double wall_lookahead = 0.6; ///< seconds of driving at the new speed checked clear on the robot's own map
};

template <class S, class F>
  requires std::same_as<std::remove_const_t<S>, AvoidanceSettings>
void visit_settings(S& s, F&& field) {
  field("horizon", s.horizon, "seconds: the velocity keeps the robot clear of its neighbours this long");
  field("margin", s.margin, "metres added to the robot's radius (a differential drive follows a velocity late)");
  field("heading_time", s.heading_time, "seconds: the turn rate is the heading error over this, within the limit");
  field("step", s.step, "seconds within which robots that already overlap part");
  field("wall_lookahead", s.wall_lookahead, "seconds of driving at the new speed checked clear on the robot's map");
}

/// Throws SchemaError naming `owner.field` for a horizon, heading time or step that is not finite and > 0, or a
/// margin or look-ahead that is negative or not finite.
void check_settings(const AvoidanceSettings& s, const std::string& owner);

/// What steer() needs of a robot this frame.
struct SteerInput {
  geometry::Pose2 pose;          ///< the robot's believed pose
  double speed = 0.0;            ///< its speed along its heading (the last one it was given), m/s
  double radius = 0.0;           ///< metres
  platform::RobotLimits limits;  ///< its speed and turn-rate limits
  double preferred_heading = 0.0;  ///< where the decider's step goes, radians in the world
  double preferred_speed = 0.0;    ///< how fast it would go there, m/s
  std::span<const orca::Neighbour> neighbours;  ///< in the world frame
};

/// The velocity a differential-drive robot is given: ORCA's velocity for `in` (the preferred velocity made safe
/// for the neighbours, the robot's radius grown by the margin), then as a speed and a turn rate: the turn rate
/// is the heading error over heading_time within max_turn_rate, the speed ORCA's along the heading (none when
/// it points more than a right angle away). With ORCA's velocity near zero the robot turns toward the
/// preferred heading on the spot.
platform::Velocity steer(const SteerInput& in, const AvoidanceSettings& settings);

/// gNeighbours for one robot: eNeighbour<to=robot, x, y, vx, vy, radius> for each neighbour its tracker holds,
/// in the robot's frame at its odometry pose, each moved on by its velocity to the frame's time. The scan is the
/// robot's laser's of the last frame, taken where the odometry of the last frame was.
class NeighbourGenerator final : public Generator {
 public:
  NeighbourGenerator(std::shared_ptr<platform::RobotPlatform> platform,
                     std::shared_ptr<const platform::ScanSource> scan, platform::NeighbourSettings settings,
                     const Alphabet& alphabet, const std::string& event = "eNeighbour");
  void reset(std::uint64_t seed) override;
  void generate(const FrameInfo& frame, EventList& out) override;
  /// Reads the platform and its robot's laser (unchanged while events are collected); writes its own tracker.
  bool concurrent() const override { return true; }
  std::string name() const override { return "neighbours(" + std::to_string(robot_) + ")"; }
  void save_state(StateWriter& out) const override;
  void load_state(StateReader& in) override;
  int robot() const { return robot_; }
  const platform::NeighbourTracker& tracker() const { return tracker_; }

 private:
  std::shared_ptr<platform::RobotPlatform> platform_;
  std::shared_ptr<const platform::ScanSource> scan_;
  platform::NeighbourSettings settings_;
  EventTypeId event_;
  int robot_;
  platform::NeighbourTracker tracker_;
  bool scanned_ = false;          ///< a frame has gone by: the laser's last scan is of it
  geometry::Pose2 scan_pose_{};   ///< the odometry of the last frame
  double scan_time_ = 0.0;        ///< its time
};

}  // namespace vwg::robot
