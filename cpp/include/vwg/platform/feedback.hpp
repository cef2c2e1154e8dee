// What the robots tell about themselves, from any platform, as event generators: their odometry
// every frame, and their collisions when they happen (ARobot "responds to" these like any other
// event; they are addressed to the robot by its id).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "vwg/alphabet.hpp"
#include "vwg/generator.hpp"
#include "vwg/platform/platform.hpp"

namespace vwg::platform {

/// Each frame, for each robot: `<event><to=id, x, y, angle, busy, commands>` — the odometry
/// estimate (with its noise, not the truth), whether the robot still executes a command, and how
/// many commands it has received (so the robot knows its last one arrived). The event type must
/// declare the fields x, y, angle (real), busy (bool) and commands (int), in this order.
class OdometryGenerator final : public Generator {
 public:
  /// `localized`: the robots whose pose their own localization gives (LocalizationGenerator), left out here;
  /// every other robot of the platform, one a λ spawned included, gets its odometry.
  OdometryGenerator(std::shared_ptr<RobotPlatform> platform, const Alphabet& alphabet,
                    const std::string& event = "eOdometry", std::vector<int> localized = {});
  void generate(const FrameInfo& frame, EventList& out) override;
  std::string name() const override { return "odometry"; }
  void save_state(StateWriter&) const override {}  // reads the platform, which keeps its own
  void load_state(StateReader& in) override { in.end(); }

 private:
  std::shared_ptr<RobotPlatform> platform_;
  EventTypeId event_;
  std::vector<int> localized_;  // sorted
};

/// For each collision since the last frame: `<event><to=robot, other>` with the other robot's id,
/// or 0 for a wall. The event type must declare the field other (int).
class CollisionGenerator final : public Generator {
 public:
  CollisionGenerator(std::shared_ptr<RobotPlatform> platform, const Alphabet& alphabet,
                     const std::string& event = "eCollision");
  void generate(const FrameInfo& frame, EventList& out) override;
  std::string name() const override { return "collisions"; }
  void save_state(StateWriter&) const override {}  // reads the platform, which keeps its own
  void load_state(StateReader& in) override { in.end(); }

 private:
  std::shared_ptr<RobotPlatform> platform_;
  EventTypeId event_;
};

}  // namespace vwg::platform
