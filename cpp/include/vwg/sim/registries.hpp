// The robot platforms and sensors by name (vwg/registry.hpp), with the simulator's registered on
// first use: the platform "sim" and its sensors "laser", "kinect" and "camera". A third party adds
// its own with add(); the Python package's registries (vwg.registry) start from these names. They
// live with the simulator because what a platform and a sensor are made from (PlatformSetup,
// SensorSetup) names the simulator's settings; the deciders are the robot's (vwg/robot/registries.hpp).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "vwg/alphabet.hpp"
#include "vwg/generator.hpp"
#include "vwg/geometry/occupancy_grid.hpp"
#include "vwg/platform/platform.hpp"
#include "vwg/registry.hpp"
#include "vwg/sim/camera.hpp"
#include "vwg/sim/depth_camera.hpp"
#include "vwg/sim/laser.hpp"
#include "vwg/sim/physics.hpp"

namespace vwg::sim {

/// What a platform is made from: the map, the robots, the simulator's settings, and options a
/// real-robot link reads (a URL, a port).
struct PlatformSetup {
  geometry::OccupancyGrid grid;
  std::vector<platform::RobotSettings> robots;
  PhysicsSettings physics{};
  std::map<std::string, std::string> options;
};

/// Robot platforms by name: "sim", the Box2D simulator (it takes no options).
Registry<platform::RobotPlatform, const PlatformSetup&>& platforms();

/// What a sensor is made from: the platform it runs on, the robot, the alphabet its events are
/// declared in, and the world's sensor settings. `scanner` is shared by the simulated range
/// sensors of a run (made from `grid` and the platform when null).
struct SensorSetup {
  std::shared_ptr<platform::RobotPlatform> platform;
  std::shared_ptr<const Alphabet> alphabet;
  int robot = 1;
  std::shared_ptr<const geometry::OccupancyGrid> grid;
  std::shared_ptr<const RangeScanner> scanner;
  LaserSpec laser{};
  DepthCameraSpec kinect{};
  CameraSpec camera{};
  std::vector<WallMarker> markers;
  std::uint64_t seed = 0;
};

/// Sensors by name, each an event generator for one robot: "laser" (gLaser), "kinect" (gKinect)
/// and "camera" (gCamera with AprilTag detection), simulated on the "sim" platform.
Registry<Generator, const SensorSetup&>& sensors();

/// The names of the ranging sensors ("laser", "kinect", and those a third party adds): they come
/// first in a frame's priority order, robot by robot (the paper's gLaser/gKinect before gCamera).
std::set<std::string>& ranging_sensors();

}  // namespace vwg::sim
