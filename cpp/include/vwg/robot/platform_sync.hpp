// Robots come and go with the string: an ARobot that a λ spawns gets a robot on the platform (a
// body in the simulator) at its believed pose, and one that leaves the string loses it. Used as an
// engine observer, after each frame, in C++ (no call into Python).
#pragma once

#include <memory>
#include <string>

#include "vwg/alphabet.hpp"
#include "vwg/engine.hpp"
#include "vwg/platform/platform.hpp"

namespace vwg::robot {

class PlatformSync {
 public:
  /// New robots get `radius` and `limits`; actors of type `actor` with attributes id, x, y, angle.
  PlatformSync(const Alphabet& alphabet, std::shared_ptr<platform::RobotPlatform> platform, double radius,
               platform::RobotLimits limits = {}, const std::string& actor = "ARobot");
  /// After a frame: add the robots that appeared in the string, remove those that left it.
  void operator()(const FrameRecord& frame);

 private:
  std::shared_ptr<platform::RobotPlatform> platform_;
  double radius_;
  platform::RobotLimits limits_;
  SymbolId actor_;
  std::size_t id_, x_, y_, angle_;  // attribute indices
};

}  // namespace vwg::robot
