// The Box2D physics world (the simulator's RobotPlatform) in Python.
#include <string>

#include "sim_convert.hpp"
#include "vwg/sim/physics.hpp"

namespace vwg::bindings {

sim::OccupancyGrid grid_from_python(py::handle grid) {
  for (const char* attr : {"data", "resolution", "origin"}) {
    if (!py::hasattr(grid, attr)) throw SchemaError("grid", std::string("expected a map with .data, .resolution and .origin; it has no .") + attr);
  }
  py::array data = py::array::ensure(grid.attr("data"));
  if (!data || data.ndim() != 2 || !data.dtype().is(py::dtype::of<std::int8_t>())) {
    throw SchemaError("grid.data", "expected a 2-D int8 array (row 0 = the bottom row)");
  }
  py::array_t<std::int8_t, py::array::c_style | py::array::forcecast> c(data);
  sim::OccupancyGrid g;
  g.height = static_cast<int>(c.shape(0));
  g.width = static_cast<int>(c.shape(1));
  g.data.assign(c.data(), c.data() + c.size());
  g.resolution = grid.attr("resolution").cast<double>();
  if (!std::isfinite(g.resolution) || g.resolution <= 0) throw SchemaError("grid.resolution", "expected a finite value > 0");
  g.origin = pose_from_python(grid.attr("origin"), "grid.origin");
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

namespace {

/// A field of a robot description: a dict key or an attribute (vwg.robotworld.RobotSpec).
py::object field_of(py::handle robot, const char* name) {
  if (py::isinstance<py::dict>(robot)) {
    py::dict d = py::reinterpret_borrow<py::dict>(robot);
    return d.contains(name) ? py::object(d[name]) : py::object(py::none());
  }
  return py::hasattr(robot, name) ? py::object(robot.attr(name)) : py::object(py::none());
}

sim::RobotSettings robot_from_python(py::handle robot, std::size_t index) {
  sim::RobotSettings r;
  const std::string where = "robots[" + std::to_string(index) + "]";
  py::object id = field_of(robot, "id");
  if (id.is_none()) throw SchemaError(where + ".id", "missing");
  r.id = id.cast<int>();
  py::object start = field_of(robot, "start");
  if (start.is_none()) throw SchemaError(where + ".start", "missing");
  r.start = pose_from_python(start, where + ".start");
  auto number = [&](const char* name, double& into) {
    py::object v = field_of(robot, name);
    if (!v.is_none()) into = v.cast<double>();
  };
  number("radius", r.radius);
  number("max_speed", r.limits.max_speed);
  number("max_turn_rate", r.limits.max_turn_rate);
  number("max_accel", r.limits.max_accel);
  number("max_turn_accel", r.limits.max_turn_accel);
  return r;
}

}  // namespace

void init_physics(py::module_& m) {
  py::class_<sim::PhysicsWorld, platform::RobotPlatform, std::shared_ptr<sim::PhysicsWorld>>(m, "PhysicsWorld", R"doc(
The Box2D world of the simulator: walls from an occupancy grid (merged into few rectangles) and
differential-drive robots that execute motion plans under speed and acceleration limits, stepped at
a fixed time step. Robots are dicts or objects with id, start (x, y, yaw), and optionally radius,
max_speed, max_turn_rate, max_accel, max_turn_accel.)doc")
      .def(py::init([](py::object grid, py::list robots, double step, double motor_noise, double odometry_noise,
                       std::uint64_t seed, int obstacle_threshold, bool walls_at_border) {
             std::vector<sim::RobotSettings> settings;
             for (std::size_t i = 0; i < robots.size(); ++i) settings.push_back(robot_from_python(robots[i], i));
             sim::PhysicsSettings ps;
             ps.step = step;
             ps.noise = sim::NoiseModel{motor_noise, odometry_noise};
             ps.seed = seed;
             ps.obstacle_threshold = obstacle_threshold;
             ps.walls_at_border = walls_at_border;
             return std::make_shared<sim::PhysicsWorld>(grid_from_python(grid), settings, ps);
           }),
           py::arg("grid"), py::arg("robots"), py::arg("step") = 0.01, py::arg("motor_noise") = 0.0,
           py::arg("odometry_noise") = 0.0, py::arg("seed") = 0, py::arg("obstacle_threshold") = 50,
           py::arg("walls_at_border") = true)
      .def_property_readonly("wall_shapes", &sim::PhysicsWorld::wall_shapes, "Rectangles the walls were merged into.");

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
