// The C++ registries (vwg/registry.hpp, vwg/robot/registries.hpp, vwg/sim/registries.hpp) in Python: the names built in
// and factories by name. vwg.registry starts its Python registries from these.
#include <map>
#include <string>

#include "sim_convert.hpp"
#include "vwg/registry.hpp"
#include "vwg/robot/registries.hpp"
#include "vwg/sim/registries.hpp"

namespace vwg::bindings {

void init_registries(py::module_& m) {
  m.def("decider_names", [] { return robot::deciders().names(); }, "The deciders registered in C++.");
  m.def("create_decider", [](const std::string& name) { return robot::deciders().create(name); }, py::arg("name"),
        "A new decider by its C++ registered name (vwg.SchemaError listing the known ones otherwise).");
  m.def("backend_names", [] { return backends().names(); }, "The backends registered in C++.");
  m.def("create_backend", [](const std::string& name) { return backends().create(name); }, py::arg("name"));
  m.def("platform_names", [] { return sim::platforms().names(); }, "The robot platforms registered in C++.");
  m.def(
      "create_platform",
      [](const std::string& name, MapArg grid, const std::vector<platform::RobotSettings>& robots,
         const sim::PhysicsSettings& physics, const std::map<std::string, std::string>& options) {
        sim::PlatformSetup setup{grid_from_python(grid), robots, physics, options};
        return sim::platforms().create(name, setup);
      },
      py::arg("name"), py::arg("grid"), py::arg("robots"), py::arg("physics") = sim::PhysicsSettings{},
      py::arg("options") = std::map<std::string, std::string>{},
      "A robot platform by its C++ registered name, with the map, the robots and the simulator's settings.");
  m.def("sensor_names", [] { return sim::sensors().names(); }, "The sensors registered in C++.");
  m.def("ranging_sensors", [] { return std::vector<std::string>(sim::ranging_sensors().begin(), sim::ranging_sensors().end()); },
        "The sensors that come first in the priority order (ranging ones).");
  m.def(
      "create_sensor",
      [](const std::string& name, std::shared_ptr<platform::RobotPlatform> platform, std::shared_ptr<Alphabet> alphabet,
         int robot, py::object grid, std::shared_ptr<const sim::RangeScanner> scanner, const sim::LaserSpec& laser,
         const sim::DepthCameraSpec& kinect, const sim::CameraSpec& camera, py::object markers,
         std::uint64_t seed) {
        sim::SensorSetup setup;
        setup.platform = std::move(platform);
        setup.alphabet = std::move(alphabet);
        setup.robot = robot;
        if (!grid.is_none()) setup.grid = std::make_shared<const geometry::OccupancyGrid>(grid_from_python(grid));
        setup.scanner = std::move(scanner);
        setup.laser = laser;
        setup.kinect = kinect;
        setup.camera = camera;
        setup.markers = wall_markers_from_python(markers);
        setup.seed = seed;
        return sim::sensors().create(name, setup);
      },
      py::arg("name"), py::arg("platform"), py::arg("alphabet"), py::arg("robot"), py::kw_only(), py::arg("grid") = py::none(),
      py::arg("scanner") = nullptr, py::arg("laser") = sim::LaserSpec{}, py::arg("kinect") = sim::DepthCameraSpec{},
      py::arg("camera") = sim::CameraSpec{}, py::arg("markers") = py::list(),
      py::arg("seed") = sim::SensorSetup{}.seed,
      "A sensor's event generator for one robot by its C++ registered name (laser, kinect, camera).");
}

}  // namespace vwg::bindings
