// The physics world, the simulator backend and the robots' feedback generators in Python.
#include <string>

#include "sim_convert.hpp"
#include "vwg/sim/feedback.hpp"
#include "vwg/sim/physics.hpp"
#include "vwg/sim/sim_backend.hpp"

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

py::dict collision_to_python(const sim::Collision& c) {
  py::dict d;
  d["robot"] = c.robot;
  d["other"] = c.other;
  d["pose"] = pose_to_python(c.pose);
  d["time"] = c.time;
  return d;
}

}  // namespace

void init_physics(py::module_& m) {
  py::class_<sim::RobotState>(m, "RobotState", "A simulated robot: true pose, odometry estimate, motion.")
      .def_readonly("id", &sim::RobotState::id)
      .def_readonly("radius", &sim::RobotState::radius)
      .def_property_readonly("pose", [](const sim::RobotState& s) { return pose_to_python(s.pose); }, "True pose (x, y, yaw).")
      .def_property_readonly("odometry", [](const sim::RobotState& s) { return pose_to_python(s.odometry); },
                             "The robot's own pose estimate (x, y, yaw), with odometry noise.")
      .def_readonly("speed", &sim::RobotState::speed)
      .def_readonly("turn_rate", &sim::RobotState::turn_rate)
      .def_readonly("busy", &sim::RobotState::busy, "Executing a motion plan.")
      .def_readonly("commands", &sim::RobotState::commands, "Motion plans received so far.")
      .def_readonly("collisions", &sim::RobotState::collisions)
      .def_readonly("travelled", &sim::RobotState::travelled, "Metres driven.")
      .def("__repr__", [](const sim::RobotState& s) {
        return "vwg.RobotState(id=" + std::to_string(s.id) + ", pose=(" + format_real(s.pose.x) + ", " +
               format_real(s.pose.y) + ", " + format_real(s.pose.theta) + "), busy=" + (s.busy ? "True" : "False") + ")";
      });

  py::class_<sim::PhysicsWorld, std::shared_ptr<sim::PhysicsWorld>>(m, "PhysicsWorld", R"doc(
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
      .def("command", [](sim::PhysicsWorld& w, int robot, py::list plan) {
             std::vector<sim::MotionStep> steps;
             for (auto item : plan) {
               py::tuple t = item.cast<py::tuple>();
               const std::string kind = t[0].cast<std::string>();
               if (kind != "turn" && kind != "drive") throw SchemaError("plan", "steps are ('turn', radians) or ('drive', metres)");
               steps.push_back(sim::MotionStep{kind == "turn" ? sim::MotionStep::Turn : sim::MotionStep::Drive, t[1].cast<double>()});
             }
             w.command(robot, std::move(steps));
           }, py::arg("robot"), py::arg("plan"),
           "Replace the robot's plan: a list of ('turn', radians) and ('drive', metres) steps.")
      .def("advance", &sim::PhysicsWorld::advance, py::arg("seconds"), py::call_guard<py::gil_scoped_release>(),
           "Step the world for `seconds` at its fixed time step.")
      .def("robot", &sim::PhysicsWorld::robot, py::arg("id"), py::return_value_policy::copy)
      .def_property_readonly("robots", [](const sim::PhysicsWorld& w) {
        return std::vector<sim::RobotState>(w.robots().begin(), w.robots().end());
      })
      .def("take_collisions", [](sim::PhysicsWorld& w) {
        py::list out;
        for (const auto& c : w.take_collisions()) out.append(collision_to_python(c));
        return out;
      }, "Collisions since the last call: dicts with robot, other (0 = a wall), pose, time.")
      .def_property_readonly("time", &sim::PhysicsWorld::time)
      .def_property_readonly("wall_shapes", &sim::PhysicsWorld::wall_shapes, "Rectangles the walls were merged into.");

  py::class_<sim::SimBackend, Backend, std::shared_ptr<sim::SimBackend>>(m, "SimBackend", R"doc(
The simulator as the geometric system G (paper Table I): α(Robot<id>) makes robot `id` execute the
Move<d> and Rotate<a> transformations it is displayed under, outermost first; end_frame steps the
physics for the frame's dt.)doc")
      .def(py::init([](std::shared_ptr<sim::PhysicsWorld> world, std::string robot, std::string move, std::string rotate) {
             return std::make_shared<sim::SimBackend>(std::move(world), sim::MotionSymbols{robot, move, rotate});
           }),
           py::arg("world"), py::arg("robot") = "Robot", py::arg("move") = "Move", py::arg("rotate") = "Rotate")
      .def_property_readonly("world", &sim::SimBackend::world);

  py::class_<sim::OdometryGenerator, Generator, std::shared_ptr<sim::OdometryGenerator>>(m, "OdometryGenerator",
      "Each frame, for each robot: event<to=id, x, y, angle, busy, commands> with its odometry estimate.")
      .def(py::init<std::shared_ptr<sim::PhysicsWorld>, const Alphabet&, const std::string&>(), py::arg("world"),
           py::arg("alphabet"), py::arg("event") = "eOdometry");
  py::class_<sim::CollisionGenerator, Generator, std::shared_ptr<sim::CollisionGenerator>>(m, "CollisionGenerator",
      "For each collision since the last frame: event<to=robot, other> (other = 0 for a wall).")
      .def(py::init<std::shared_ptr<sim::PhysicsWorld>, const Alphabet&, const std::string&>(), py::arg("world"),
           py::arg("alphabet"), py::arg("event") = "eCollision");

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
