#include "vwg/sim/registries.hpp"

#include <mutex>

#include "vwg/error.hpp"
#include "vwg/perception/camera_generator.hpp"
#include "vwg/sim/camera_source.hpp"
#include "vwg/sim/raycast.hpp"

namespace vwg::sim {

Registry<platform::RobotPlatform, const PlatformSetup&>& platforms() {
  static Registry<platform::RobotPlatform, const PlatformSetup&> registry("platform");
  static std::once_flag built_in;
  std::call_once(built_in, [] {
    auto* r = &registry;
    r->add("sim", [](const PlatformSetup& setup) -> std::shared_ptr<platform::RobotPlatform> {
      if (!setup.options.empty()) {
        throw SchemaError("platform sim", "unknown option '" + setup.options.begin()->first + "' (it takes none)");
      }
      return std::make_shared<PhysicsWorld>(setup.grid, setup.robots, setup.physics);
    });
  });
  return registry;
}

namespace {

/// The simulator under a sensor, or a clear error: simulated sensors look at the simulated world.
std::shared_ptr<PhysicsWorld> simulator_of(const SensorSetup& setup, const std::string& sensor) {
  auto world = std::dynamic_pointer_cast<PhysicsWorld>(setup.platform);
  if (!world) {
    throw SchemaError("sensor " + sensor, "is simulated and needs the sim platform, not '" +
                                              (setup.platform ? setup.platform->name() : std::string("none")) + "'");
  }
  if (!setup.alphabet) throw SchemaError("sensor " + sensor, "needs the alphabet its events are declared in");
  return world;
}

std::shared_ptr<const RangeScanner> scanner_of(const SensorSetup& setup, const std::string& sensor) {
  auto world = simulator_of(setup, sensor);
  if (setup.scanner) return setup.scanner;
  if (!setup.grid) throw SchemaError("sensor " + sensor, "needs the map (grid) or a scanner");
  return std::make_shared<RangeScanner>(std::make_shared<GridRaycaster>(*setup.grid), world);
}

}  // namespace

Registry<Generator, const SensorSetup&>& sensors() {
  static Registry<Generator, const SensorSetup&> registry("sensor");
  static std::once_flag built_in;
  std::call_once(built_in, [] {
    auto* r = &registry;
    r->add("laser", [](const SensorSetup& s) -> std::shared_ptr<Generator> {
      auto scanner = scanner_of(s, "laser");  // checks the alphabet too, before it is read
      return std::make_shared<LaserGenerator>(std::move(scanner), s.robot, s.laser, *s.alphabet);
    });
    r->add("kinect", [](const SensorSetup& s) -> std::shared_ptr<Generator> {
      auto scanner = scanner_of(s, "kinect");
      return std::make_shared<KinectGenerator>(std::move(scanner), s.robot, s.kinect, *s.alphabet);
    });
    r->add("camera", [](const SensorSetup& s) -> std::shared_ptr<Generator> {
      auto world = simulator_of(s, "camera");
      if (!s.grid) throw SchemaError("sensor camera", "needs the map (grid)");
      auto renderer = std::make_shared<CameraRenderer>(*s.grid, s.markers, s.camera, kObstacleThreshold,
                                                      s.seed * 1009 + static_cast<std::uint64_t>(s.robot));
      perception::CameraGeneratorSettings settings;
      settings.robot = s.robot;
      settings.intrinsics = renderer->apriltag_intrinsics();
      for (const WallMarker& m : s.markers) settings.tag_sizes[m.id] = m.size;
      settings.period = s.camera.period;
      auto source = std::make_shared<SimulatedCamera>(world, s.robot, std::move(renderer));
      return std::make_shared<perception::CameraGenerator>(std::move(source), settings, *s.alphabet);
    });
  });
  return registry;
}

std::set<std::string>& ranging_sensors() {
  static std::set<std::string> ranging{"laser", "kinect"};
  return ranging;
}

}  // namespace vwg::sim
