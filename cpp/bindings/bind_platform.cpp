// The robot platform in Python (vwg/platform/*.hpp): RobotPlatform — implemented by the simulator
// (PhysicsWorld) and subclassable in Python, so a real-robot link written in Python plugs into
// the same frame path — the robots' states, collisions and settings, the motion backend, the
// feedback generators, and the rule that turns a laser scan into eLaser events.
#include <algorithm>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sim_convert.hpp"
#include "vwg/geometry/pose.hpp"
#include "vwg/platform/feedback.hpp"
#include "vwg/platform/laser_scan.hpp"
#include "vwg/platform/motion.hpp"
#include "vwg/platform/motion_follower.hpp"
#include "vwg/platform/platform.hpp"

namespace vwg::bindings {

namespace {

using platform::Collision;
using platform::MotionStep;
using platform::RobotPlatform;
using platform::RobotSettings;
using platform::RobotState;

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// A 1-D array of `field`, converted to T (ranges become float32, as a LaserScan carries them).
template <class Array>
Array vector_of(py::handle obj, const std::string& field, const char* what) {
  auto a = Array::ensure(obj);
  if (!a) {
    PyErr_Clear();
    throw SchemaError(field, std::string("expected a 1-D array of numbers (") + what + ")");
  }
  if (a.ndim() != 1) throw SchemaError(field, "expected a 1-D array, got " + std::to_string(a.ndim()) + " dimensions");
  return a;
}

/// (dist, angle): the events' columns as two float64 arrays.
std::pair<py::array_t<double>, py::array_t<double>> events_to_python(const platform::ScanEvents& hits) {
  py::array_t<double> dist(static_cast<py::ssize_t>(hits.size())), angle(static_cast<py::ssize_t>(hits.size()));
  std::copy(hits.dist().begin(), hits.dist().end(), dist.mutable_data());
  std::copy(hits.angle().begin(), hits.angle().end(), angle.mutable_data());
  return {dist, angle};
}

constexpr const char* kRangesDoc = "metres, float32; NaN where nothing is known";

py::list steps_to_python(const std::vector<MotionStep>& steps) {
  py::list out;
  for (const MotionStep& s : steps) {
    if (s.kind == MotionStep::Steer) {
      out.append(py::make_tuple("steer", s.amount, s.rate));
    } else {
      out.append(py::make_tuple(s.kind == MotionStep::Turn ? "turn" : "drive", s.amount));
    }
  }
  return out;
}

/// A platform written in Python: each virtual call runs the Python method (taking the GIL). What
/// robots() returns is kept here, as C++ callers hold a reference to it until the next call.
class PyRobotPlatform final : public RobotPlatform {
 public:
  void add_robot(const RobotSettings& robot) override { PYBIND11_OVERRIDE_PURE(void, RobotPlatform, add_robot, robot); }
  void remove_robot(int id) override { PYBIND11_OVERRIDE_PURE(void, RobotPlatform, remove_robot, id); }
  void command(int id, std::vector<MotionStep> steps) override {
    py::gil_scoped_acquire gil;
    py::function fn = py::get_override(static_cast<const RobotPlatform*>(this), "command");
    if (!fn) throw Error("a vwg.RobotPlatform subclass must define command(self, robot, steps)");
    fn(id, steps_to_python(steps));
  }
  void advance(double seconds) override { PYBIND11_OVERRIDE_PURE(void, RobotPlatform, advance, seconds); }
  const std::vector<RobotState>& robots() const override {
    py::gil_scoped_acquire gil;
    py::function fn = py::get_override(static_cast<const RobotPlatform*>(this), "robots");
    if (!fn) throw Error("a vwg.RobotPlatform subclass must define robots(self) -> list of vwg.RobotState");
    robots_ = fn().cast<std::vector<RobotState>>();
    return robots_;
  }
  std::vector<Collision> take_collisions() override {
    PYBIND11_OVERRIDE_PURE(std::vector<Collision>, RobotPlatform, take_collisions, );
  }
  double time() const override { PYBIND11_OVERRIDE_PURE(double, RobotPlatform, time, ); }
  std::string name() const override { PYBIND11_OVERRIDE_PURE(std::string, RobotPlatform, name, ); }
  /// A Python platform is saved only by its own save_state(self) -> bytes and load_state(self, data).
  void save_state(StateWriter& out) const override {
    py::gil_scoped_acquire gil;
    py::function fn = py::get_override(static_cast<const RobotPlatform*>(this), "save_state");
    if (!fn) RobotPlatform::save_state(out);
    const std::string bytes = fn().cast<std::string>();
    out.raw(bytes.data(), bytes.size());
  }
  void load_state(StateReader& in) override {
    py::gil_scoped_acquire gil;
    py::function fn = py::get_override(static_cast<const RobotPlatform*>(this), "load_state");
    if (!fn) RobotPlatform::load_state(in);
    std::string bytes(in.left(), '\0');
    in.raw(bytes.data(), bytes.size(), "the state");
    fn(py::bytes(bytes));
  }

 private:
  mutable std::vector<RobotState> robots_;
};

}  // namespace

std::vector<MotionStep> steps_from_python(py::handle steps) {
  std::vector<MotionStep> out;
  for (auto item : steps) {
    py::tuple t = item.cast<py::tuple>();
    const std::string kind = t.size() >= 1 ? t[0].cast<std::string>() : "";
    if (kind == "steer" && t.size() == 3) {
      out.push_back(MotionStep{MotionStep::Steer, t[1].cast<double>(), t[2].cast<double>()});
      continue;
    }
    if ((kind != "turn" && kind != "drive") || t.size() != 2) {
      throw SchemaError("steps", "steps are ('turn', radians), ('drive', metres) or ('steer', m/s, rad/s)");
    }
    out.push_back(MotionStep{kind == "turn" ? MotionStep::Turn : MotionStep::Drive, t[1].cast<double>()});
  }
  return out;
}

void init_platform(py::module_& m) {
  py::class_<RobotState>(m, "RobotState", "A robot as a platform knows it after its last step.")
      .def(py::init([](int id, PoseArg pose, py::object odometry, double radius, bool busy, std::uint64_t commands,
                       std::uint64_t collisions, double travelled, double speed, double turn_rate) {
             RobotState s;
             s.id = id;
             s.pose = pose_from_python(pose, "pose");
             s.odometry = odometry.is_none() ? s.pose : pose_from_python(odometry, "odometry");
             s.radius = radius;
             s.busy = busy;
             s.commands = commands;
             s.collisions = collisions;
             s.travelled = travelled;
             s.speed = speed;
             s.turn_rate = turn_rate;
             return s;
           }),
           py::arg("id"), py::arg("pose"), py::arg("odometry") = py::none(), py::kw_only(), py::arg("radius") = platform::kDefaultRobotRadius,
           py::arg("busy") = RobotState{}.busy, py::arg("commands") = RobotState{}.commands,
           py::arg("collisions") = RobotState{}.collisions, py::arg("travelled") = RobotState{}.travelled,
           py::arg("speed") = RobotState{}.speed, py::arg("turn_rate") = RobotState{}.turn_rate)
      .def_readonly("id", &RobotState::id)
      .def_readonly("radius", &RobotState::radius)
      .def_property_readonly("pose", [](const RobotState& s) { return pose_to_python(s.pose); },
                             "The platform's pose (x, y, yaw): the truth in the simulator.")
      .def_property_readonly("odometry", [](const RobotState& s) { return pose_to_python(s.odometry); },
                             "The robot's own pose estimate (x, y, yaw), with odometry noise.")
      .def_readonly("speed", &RobotState::speed)
      .def_readonly("turn_rate", &RobotState::turn_rate)
      .def_readonly("busy", &RobotState::busy, "Executing a motion command.")
      .def_readonly("commands", &RobotState::commands, "Motion commands received so far.")
      .def_readonly("collisions", &RobotState::collisions)
      .def_readonly("travelled", &RobotState::travelled, "Metres driven.")
      .def("__repr__", [](const RobotState& s) {
        return "vwg.RobotState(id=" + std::to_string(s.id) + ", pose=(" + format_real(s.pose.x) + ", " +
               format_real(s.pose.y) + ", " + format_real(s.pose.theta) + "), busy=" + (s.busy ? "True" : "False") + ")";
      });

  py::class_<Collision>(m, "Collision", "A robot touched a wall (other = 0) or another robot.")
      .def(py::init([](int robot, int other, PoseArg pose, double time) {
             return Collision{robot, other, pose_from_python(pose, "pose"), time};
           }),
           py::arg("robot"), py::arg("other"), py::arg("pose") = pose_to_python(Collision{}.pose), py::arg("time") = Collision{}.time)
      .def_readonly("robot", &Collision::robot)
      .def_readonly("other", &Collision::other)
      .def_property_readonly("pose", [](const Collision& c) { return pose_to_python(c.pose); })
      .def_readonly("time", &Collision::time);

  py::class_<platform::MotionFollower>(m, "MotionFollower", R"doc(
A motion plan followed on a pose: a trapezoidal speed profile within the robot's limits, recomputed
at every tick from where the pose says the robot is, so a step ends when the pose says it is done.
The simulator runs it on the true pose at every physics step; a real robot's link on its odometry
at every control tick — the same velocities from the same poses (paper test 3).)doc")
      .def(py::init([](const RobotSettings& robot, double tolerance) { return platform::MotionFollower(robot.limits, tolerance); }),
           py::arg("robot"), py::arg("tolerance") = platform::MotionFollower::kDefaultTolerance,
           "The follower of a robot with these limits; a step that meant to land on its end is done within `tolerance` (m or rad).")
      .def("command", [](platform::MotionFollower& f, py::handle steps) { f.command(steps_from_python(steps)); },
           py::arg("steps"), "Replace the plan: a list of ('turn', radians) and ('drive', metres); [] brings the robot to rest.")
      .def("tick", [](platform::MotionFollower& f, PoseArg pose, double dt) {
             const platform::Velocity v = f.tick(pose_from_python(pose, "pose"), dt);
             return py::make_tuple(v.speed, v.turn_rate);
           }, py::arg("pose"), py::arg("dt"), "The velocities (m/s, rad/s) to hold for the next dt seconds, the robot being at pose now.")
      .def("settle", [](platform::MotionFollower& f, PoseArg pose) { f.settle(pose_from_python(pose, "pose")); },
           py::arg("pose"), "After the robot moved: end a step that reached its end (keeps busy exact).")
      .def("stop", &platform::MotionFollower::stop, "Drop the plan and command no motion at once.")
      .def("halt", &platform::MotionFollower::halt, "Command no motion at once, keeping the plan (it goes on from rest).")
      .def_property_readonly("busy", &platform::MotionFollower::busy)
      .def_property_readonly("velocity", [](const platform::MotionFollower& f) {
        return py::make_tuple(f.velocity().speed, f.velocity().turn_rate);
      }, "The last commanded (speed, turn_rate).");

  m.def("quantize_pose", [](PoseArg pose) { return pose_to_python(platform::quantize_pose(pose_from_python(pose, "pose"))); },
        py::arg("pose"),
        "The pose at the simulator's float resolution (x, y rounded to float; the angle wrapped into [-π, π] and rounded): "
        "every platform reports poses so, and a pose carried through a link comes back bit for bit.");

  m.def("laser_events",
        [](py::handle ranges, double angle_min, double angle_increment, double range_min, double range_max,
           const std::optional<PoseArg>& seen_from) {
          const FloatArray r = vector_of<FloatArray>(ranges, "ranges", kRangesDoc);
          platform::ScanEvents hits;
          platform::laser_events({r.data(), static_cast<std::size_t>(r.size())}, angle_min, angle_increment, range_min,
                                 range_max, hits);
          auto [dist, angle] = events_to_python(hits);
          if (seen_from) {
            const geometry::Pose2 from = pose_from_python(*seen_from, "seen_from");
            double* d = dist.mutable_data();
            double* a = angle.mutable_data();
            for (py::ssize_t i = 0; i < dist.size(); ++i) {
              const geometry::Polar now = geometry::seen_from(from, {d[i], a[i]});
              d[i] = now.dist;
              a[i] = now.bearing;
            }
          }
          return std::make_pair(dist, angle);
        },
        py::arg("ranges"), py::arg("angle_min"), py::arg("angle_increment"), py::arg("range_min"), py::arg("range_max"),
        py::arg("seen_from") = py::none(),
        R"doc(The eLaser events of a laser scan laid out as sensor_msgs/LaserScan lays it out (beam i at
angle_min + i·angle_increment): (dist, angle), two float64 arrays, one entry for each beam that met an
obstacle, in beam order. The one rule of the simulated and the real robots' lasers (REP 117): a reading in
[range_min, range_max) is an obstacle; a reading >= range_max (+Inf included) is no return, as drivers
that report no return as range_max mean it; -Inf is an obstacle at range_min; NaN and readings below
range_min are no measurement. Ranges are taken as float32 (range_max compared as float32 too).
With ``seen_from`` (x ahead, y left, theta: where the robot was when the scan was taken, in its frame
now), each hit is given as seen from where the robot is now.)doc");
  m.def("laser_events",
        [](py::handle ranges, py::handle angles, double range_min, double range_max) {
          const FloatArray r = vector_of<FloatArray>(ranges, "ranges", kRangesDoc);
          const DoubleArray a = vector_of<DoubleArray>(angles, "angles", "radians from the heading");
          platform::ScanEvents hits;
          platform::laser_events({r.data(), static_cast<std::size_t>(r.size())},
                                 {a.data(), static_cast<std::size_t>(a.size())}, range_min, range_max, hits);
          return events_to_python(hits);
        },
        py::arg("ranges"), py::arg("angles"), py::arg("range_min"), py::arg("range_max"),
        "The same for beams at the given angles (as the simulated laser's: LaserGenerator.angles).");

  py::class_<RobotPlatform, PyRobotPlatform, std::shared_ptr<RobotPlatform>>(m, "RobotPlatform", R"doc(
Where frames meet robots: the Box2D simulator (PhysicsWorld) or a real robot's link. Subclass it in
Python and define add_robot(settings), remove_robot(id), command(robot, steps) — steps are
('turn', radians) and ('drive', metres), the latest command replacing the previous one — advance(seconds),
robots() -> list of RobotState, take_collisions() -> list of Collision, time() and name().)doc")
      .def(py::init<>())
      .def("add_robot", &RobotPlatform::add_robot, py::arg("settings"))
      .def("remove_robot", &RobotPlatform::remove_robot, py::arg("id"))
      .def("command", [](RobotPlatform& p, int robot, py::handle steps) { p.command(robot, steps_from_python(steps)); },
           py::arg("robot"), py::arg("steps"),
           "Replace the robot's command: a list of ('turn', radians) and ('drive', metres) steps.")
      .def("advance", &RobotPlatform::advance, py::arg("seconds"), py::call_guard<py::gil_scoped_release>(),
           "Let `seconds` pass on the platform.")
      .def("robots", [](const RobotPlatform& p) { return p.robots(); }, "Every robot's state.")
      .def("robot", &RobotPlatform::robot, py::arg("id"), py::return_value_policy::copy)
      .def("find_robot", [](const RobotPlatform& p, int id) -> std::optional<RobotState> {
             const RobotState* s = p.find_robot(id);
             return s != nullptr ? std::optional<RobotState>(*s) : std::nullopt;
           }, py::arg("id"), "Robot `id`'s state, or None when the platform has no such robot (a λ took it out of the string).")
      .def("take_collisions", &RobotPlatform::take_collisions, "The collisions since the last call.")
      .def("time", &RobotPlatform::time, "The platform's clock, seconds.")
      .def("name", &RobotPlatform::name)
      .def("save_state", &saved_state<RobotPlatform>, "Everything that decides what the platform does next, as bytes (a saved run); a real robot's "
         "platform refuses. A Python platform may define save_state(self) -> bytes and load_state(self, data).")
      .def("load_state", [](RobotPlatform& p, const py::bytes& data, std::optional<double> seconds) {
        load_saved_state(p, data, "platform " + p.name(), seconds);
      }, py::arg("data"), py::arg("seconds") = py::none(),
      "Back to what save_state() returned, on a platform made as the saved one was. `seconds`: the saved run's "
      "simulated time, which nothing in the state may exceed (a state from someone else cannot ask for years).");

  py::class_<platform::MotionBackend, Backend, std::shared_ptr<platform::MotionBackend>>(m, "MotionBackend", R"doc(
φ on a robot platform (paper Table I): α(Robot<id>) commands robot `id` with the Move<d> and
Rotate<a> transformations it is displayed under, outermost first; the end of a frame lets its dt
pass on the platform. The same string drives the simulator and a real robot.)doc")
      .def(py::init([](std::shared_ptr<RobotPlatform> platform, std::string robot, std::string move, std::string rotate) {
             return std::make_shared<platform::MotionBackend>(std::move(platform),
                                                             platform::MotionSymbols{robot, move, rotate});
           }),
           py::arg("platform"), py::arg("robot") = "Robot", py::arg("move") = "Move", py::arg("rotate") = "Rotate")
      .def_property_readonly("platform", &platform::MotionBackend::platform);

  py::class_<platform::OdometryGenerator, Generator, std::shared_ptr<platform::OdometryGenerator>>(m, "OdometryGenerator",
      "Each frame, for each robot of the platform but those `localized` (whose pose their LocalizationGenerator "
      "gives): event<to=id, x, y, angle, busy, commands> (its odometry).")
      .def(py::init<std::shared_ptr<RobotPlatform>, const Alphabet&, const std::string&, std::vector<int>>(),
           py::arg("platform"), py::arg("alphabet"), py::arg("event") = "eOdometry",
           py::arg("localized") = std::vector<int>{});
  py::class_<platform::CollisionGenerator, Generator, std::shared_ptr<platform::CollisionGenerator>>(m, "CollisionGenerator",
      "For each collision since the last frame: event<to=robot, other> (other = 0 for a wall).")
      .def(py::init<std::shared_ptr<RobotPlatform>, const Alphabet&, const std::string&>(), py::arg("platform"),
           py::arg("alphabet"), py::arg("event") = "eCollision");
}

}  // namespace vwg::bindings
