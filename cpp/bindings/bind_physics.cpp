// The Box2D physics world (the simulator's RobotPlatform) in Python.
#include <algorithm>
#include <cmath>
#include <string>

#include "sim_convert.hpp"
#include "vwg/sim/physics.hpp"
#include "vwg/text.hpp"

namespace vwg::bindings {

sim::OccupancyGrid grid_from_python(py::handle grid) {
  sim::OccupancyGrid g;
  if (py::isinstance<sim::OccupancyGrid>(grid)) {
    g = grid.cast<const sim::OccupancyGrid&>();  // vwg.io.maps.OccupancyGrid: the C++ grid itself
  } else {
    for (const char* attr : {"data", "resolution", "origin"}) {
      if (!py::hasattr(grid, attr)) throw SchemaError("grid", std::string("expected a map with .data, .resolution and .origin; it has no .") + attr);
    }
    py::array data = py::array::ensure(grid.attr("data"));
    if (!data || data.ndim() != 2 || !data.dtype().is(py::dtype::of<std::int8_t>())) {
      throw SchemaError("grid.data", "expected a 2-D int8 array (row 0 = the bottom row)");
    }
    py::array_t<std::int8_t, py::array::c_style | py::array::forcecast> c(data);
    g.height = static_cast<int>(c.shape(0));
    g.width = static_cast<int>(c.shape(1));
    g.data.assign(c.data(), c.data() + c.size());
    g.resolution = grid.attr("resolution").cast<double>();
    g.origin = pose_from_python(grid.attr("origin"), "grid.origin");
  }
  // Metres per cell, and the map's extent, within what Box2D's floats hold (platform::kMaxCoordinate).
  if (!std::isfinite(g.resolution) || g.resolution < 1e-4 || g.resolution > 100) {
    throw SchemaError("grid.resolution", "expected 0.0001 to 100 metres per cell, got " + format_real(g.resolution));
  }
  const double extent = std::max(g.width, g.height) * g.resolution;
  if (std::abs(g.origin.x) + extent > platform::kMaxCoordinate || std::abs(g.origin.y) + extent > platform::kMaxCoordinate ||
      std::abs(g.origin.theta) > platform::kMaxAngle) {
    throw SchemaError("grid.origin", "expected a map within ±" + format_real(platform::kMaxCoordinate) + " m");
  }
  return g;
}

sim::Pose2 pose_from_python(py::handle pose, const std::string& field) {
  py::sequence s = py::reinterpret_borrow<py::sequence>(pose);
  if (!py::isinstance<py::sequence>(pose) || py::len(s) != 3) throw SchemaError(field, "expected (x, y, yaw)");
  sim::Pose2 p{s[0].cast<double>(), s[1].cast<double>(), s[2].cast<double>()};
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.theta)) throw SchemaError(field, "expected finite numbers");
  return p;
}

py::tuple pose_to_python(const sim::Pose2& p) { return py::make_tuple(p.x, p.y, p.theta); }

void init_physics(py::module_& m) {
  py::class_<sim::PhysicsWorld, platform::RobotPlatform, std::shared_ptr<sim::PhysicsWorld>>(m, "PhysicsWorld", R"doc(
The Box2D world of the simulator: walls from an occupancy grid (merged into few rectangles) and
differential-drive robots (vwg.RobotSettings) that execute motion plans under speed and acceleration
limits, stepped at the fixed time step of `settings`.)doc")
      .def(py::init([](MapArg grid, const std::vector<sim::RobotSettings>& robots, const sim::PhysicsSettings& settings) {
             return std::make_shared<sim::PhysicsWorld>(grid_from_python(grid), robots, settings);
           }),
           py::arg("grid"), py::arg("robots"), py::arg("settings") = sim::PhysicsSettings{})
      .def("drive", &sim::PhysicsWorld::drive, py::arg("robot"), py::arg("speed"), py::arg("turn_rate"),
           "Hold the robot at these velocities (m/s, rad/s) from now on, as a base driven by velocity commands "
           "(a fake robot behind a link); its plan is dropped, and the next command() ends it.")
      .def("set_person", &sim::PhysicsWorld::set_person, py::arg("id"), py::arg("x"), py::arg("y"), py::arg("vx"),
           py::arg("vy"), py::arg("radius"),
           "Put person `id` (a kinematic disc, made at its first call) at (x, y), moving at (vx, vy).")
      .def_property_readonly("people", [](const sim::PhysicsWorld& w) {
        py::list out;
        for (const sim::PhysicsWorld::Person& p : w.people()) {
          out.append(py::dict(py::arg("id") = p.id, py::arg("x") = p.x, py::arg("y") = p.y, py::arg("vx") = p.vx,
                              py::arg("vy") = p.vy, py::arg("radius") = p.radius));
        }
        return out;
      }, "The people, in the order they were first set: [{id, x, y, vx, vy, radius}].")
      .def_property_readonly("wall_shapes", &sim::PhysicsWorld::wall_shapes, "Rectangles the walls were merged into.")
      .def_property_readonly("journal_bytes", &sim::PhysicsWorld::journal_bytes,
                             "Bytes of its journal: every call made to it, which its saved state holds.");

  py::class_<BackendGroup, Backend, std::shared_ptr<BackendGroup>>(m, "BackendGroup",
      "Several backends as one: every call goes to each, in order (e.g. the simulator, then a renderer).")
      .def(py::init([](py::list backends) {
             std::vector<std::shared_ptr<Backend>> list;
             for (auto b : backends) list.push_back(b.cast<std::shared_ptr<Backend>>());
             return std::make_shared<BackendGroup>(std::move(list));
           }), py::arg("backends"), py::keep_alive<1, 2>())
      .def_property_readonly("backends", &BackendGroup::backends);
}

}  // namespace vwg::bindings
