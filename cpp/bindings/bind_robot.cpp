// The case-study actor ARobot and its deciders in Python; deciders may be written in Python.
#include <algorithm>
#include <vector>
#include <string>

#include "python_budget.hpp"
#include "sim_convert.hpp"
#include "vwg/robot/arobot.hpp"
#include "vwg/robot/decider.hpp"
#include "vwg/robot/orders.hpp"
#include "vwg/plan/ompl_planner.hpp"
#include "vwg/robot/planners.hpp"

namespace vwg::bindings {

namespace {

/// What a Python decider sees; valid only during decide() (the arrays are views of the robot's
/// grid and path, which the next frame may replace).
struct PyDecisionInput {
  const robot::DecisionInput* in = nullptr;
  const robot::DecisionInput& get() const {
    if (!in) throw SchemaError("DecisionInput", "is only available during decide()");
    return *in;
  }
};

class PyDecider : public robot::Decider {
 public:
  robot::Decision decide(const robot::DecisionInput& in) override {
    py::gil_scoped_acquire gil;
    PythonCallTimer timer([this] { return "the Python decider " + name() + ".decide"; });
    py::function fn = py::get_override(static_cast<const robot::Decider*>(this), "decide");
    if (!fn) throw Error("a vwg.Decider subclass must define decide(self, robot)");
    auto holder = std::make_shared<PyDecisionInput>(PyDecisionInput{&in});
    py::object result;
    try {
      result = fn(py::cast(holder));
    } catch (...) {
      holder->in = nullptr;
      throw;
    }
    holder->in = nullptr;
    robot::Decision d;
    if (result.is_none()) {
      d.kind = robot::Decision::Kind::NoPath;
      return d;
    }
    py::sequence s = result.cast<py::sequence>();
    if (py::len(s) < 2 || py::len(s) > 3) {
      throw SchemaError(name() + ".decide", "return (turn, distance), (turn, distance, path) or None for no way");
    }
    d.turn = s[0].cast<double>();
    d.distance = s[1].cast<double>();
    if (!std::isfinite(d.turn) || !std::isfinite(d.distance)) throw SchemaError(name() + ".decide", "turn and distance must be finite");
    if (py::len(s) == 3) {
      for (const auto& p : points_from_python(s[2], name() + ".decide path")) {
        d.path.push_back(p.x);
        d.path.push_back(p.y);
      }
    } else {
      d.path = {in.pose.x, in.pose.y, in.pose.x + d.distance * std::cos(in.pose.theta + d.turn),
                in.pose.y + d.distance * std::sin(in.pose.theta + d.turn)};
    }
    return d;
  }
  std::string name() const override {
    // The class's `name` if a Python subclass sets one; read on the type, since on the instance a
    // base-class property would call this function again.
    py::gil_scoped_acquire gil;
    return python_type_name(py::cast(this));
  }
  void save_state(StateWriter& out) const override {
    py::gil_scoped_acquire gil;
    save_python_state(py::cast(this), out, "decider " + name());
  }
  void load_state(StateReader& in) override {
    py::gil_scoped_acquire gil;
    load_python_state(py::cast(this), in, "decider " + name());
  }
};

/// A read-only numpy view of a blob's data that holds the blob (not the short-lived DecisionInput):
/// kept past decide(), it stays valid, and it keeps what it showed, because the actor's next write
/// sees the blob shared and writes to a copy.
template <class T>
py::array blob_view(std::shared_ptr<const Blob> blob, const T* data, std::vector<py::ssize_t> shape) {
  auto* held = new std::shared_ptr<const Blob>(std::move(blob));
  py::capsule owner(held, [](void* p) { delete static_cast<std::shared_ptr<const Blob>*>(p); });
  py::array a = py::array_t<T>(shape, {}, data, owner);
  a.attr("flags").attr("writeable") = false;
  return a;
}

geometry::MapGeometry geometry_of(py::handle grid) { return geometry::MapGeometry::of(grid_from_python(grid)); }

}  // namespace

void init_robot(py::module_& m) {
  py::class_<PyDecisionInput, std::shared_ptr<PyDecisionInput>>(m, "DecisionInput", R"doc(
What the robot knows when it decides (read it during decide(); the arrays it gives, ``grid`` and
``path``, may be kept: they hold their data and do not change afterwards): its id, believed pose
(x, y, yaw), goal point, radius (with the clearance it keeps), step length, its map (int16 numpy
view: -1 unknown, 0 free, 100 wall, 101 seen obstacle, 1000 + tag id a marker), the map's
resolution and origin, the current path (N×2) and a seed for random choices.)doc")
      .def_property_readonly("robot", [](const PyDecisionInput& i) { return i.get().robot; })
      .def_property_readonly("pose", [](const PyDecisionInput& i) { return pose_to_python(i.get().pose); })
      .def_property_readonly("goal", [](const PyDecisionInput& i) { return py::make_tuple(i.get().goal_x, i.get().goal_y); })
      .def_property_readonly("radius", [](const PyDecisionInput& i) { return i.get().radius; })
      .def_property_readonly("step_length", [](const PyDecisionInput& i) { return i.get().step_length; })
      .def_property_readonly("seed", [](const PyDecisionInput& i) { return i.get().seed; })
      .def_property_readonly("resolution", [](const PyDecisionInput& i) { return i.get().geometry->resolution; })
      .def_property_readonly("origin", [](const PyDecisionInput& i) { return pose_to_python(i.get().geometry->origin); })
      .def_property_readonly("grid", [](const PyDecisionInput& i) {
        const auto& in = i.get();
        return py::reinterpret_borrow<py::array_t<std::int16_t>>(
            blob_view(in.map, in.map->view<std::int16_t>().data(), {in.geometry->height, in.geometry->width}));
      }, "The robot's map (int16, read-only); safe to keep: it does not change afterwards.")
      .def_property_readonly("path", [](const PyDecisionInput& i) -> py::array_t<double> {
        const auto& in = i.get();
        const py::ssize_t n = static_cast<py::ssize_t>(in.path.size() / 2);
        if (in.path_owner) return py::reinterpret_borrow<py::array_t<double>>(blob_view(in.path_owner, in.path.data(), {n, 2}));
        py::array_t<double> copy({n, py::ssize_t{2}});  // a path not held by a blob: copied
        std::copy(in.path.begin(), in.path.end(), copy.mutable_data());
        return copy;
      }, "The current plan (N×2, read-only); safe to keep: it does not change afterwards.")
      .def("segment_clear", [](const PyDecisionInput& i, double x0, double y0, double x1, double y1) {
             const auto& in = i.get();
             return robot::segment_clear(*in.map, *in.geometry, x0, y0, x1, y1, in.radius);
           }, py::arg("x0"), py::arg("y0"), py::arg("x1"), py::arg("y1"),
           "Whether the robot (its radius and clearance) can move straight from (x0, y0) to (x1, y1) on its map.")
      .def("follow", [](const PyDecisionInput& i, py::object points) -> py::object {
             std::vector<double> xy;
             for (const auto& p : points_from_python(points, "points")) {
               xy.push_back(p.x);
               xy.push_back(p.y);
             }
             robot::Decision d;
             if (!robot::follow_path(i.get(), xy, d)) return py::none();
             return py::make_tuple(d.turn, d.distance);
           }, py::arg("points"), "(turn, distance) towards the farthest reachable point of a path within a step, or None.");

  py::class_<robot::Decider, PyDecider, std::shared_ptr<robot::Decider>>(m, "Decider", R"doc(
The decision inside λ(ARobot, eDecide) (paper test 1). Subclass it in Python and define
``decide(self, robot: DecisionInput)`` returning ``(turn, distance)`` — turn on the spot, then drive —
optionally with a path (N×2 points) to show, or None when there is no way. Built-in deciders:
RandomDecider, AStarDecider, DStarLiteDecider, OmplDecider.)doc")
      .def(py::init<>())
      .def_property_readonly("name", &robot::Decider::name)
      .def("save_state", &saved_state<robot::Decider>, "What it keeps between decisions, as bytes (a saved run). A Python subclass may define "
         "save_state(self) -> bytes and load_state(self, data); without them its attributes are kept "
         "(numbers, text, lists, dicts, numpy arrays and random generators; others are refused by name).")
      .def("load_state", [](robot::Decider& d, const py::bytes& data) { load_saved_state(d, data, "decider " + d.name()); },
           py::arg("data"), "Back to what save_state() returned, before the next decision.");
  py::class_<robot::RandomDecider, robot::Decider, std::shared_ptr<robot::RandomDecider>>(m, "RandomDecider",
      "The paper's first algorithm: random clear moves until the goal happens to be reached.")
      .def(py::init<>());
  py::class_<robot::GridDecider, robot::Decider, std::shared_ptr<robot::GridDecider>>(m, "GridDecider", R"doc(
Shortest paths on the robot's own map, inflated by its radius: full A* (8-connected, √2 diagonals,
no corner cutting, Euclidean heuristic, obstacles infinite — the paper's second algorithm), Jump
Point Search (A*'s path lengths, fewer cells expanded) or D* Lite, which repairs its search as
obstacles appear. Replans when the path becomes blocked. heuristic: "euclidean" (the paper's) or
"octile" (A* and JPS only: exact on an open grid, so the same lengths with fewer cells expanded;
registered as "astar-octile" and "jps-octile").)doc")
      .def(py::init([](const std::string& algorithm, const std::string& heuristic) {
             using Algorithm = robot::GridDecider::Algorithm;
             if (algorithm != "astar" && algorithm != "dstar" && algorithm != "jps")
               throw SchemaError("algorithm", "expected 'astar', 'dstar' or 'jps', got '" + algorithm + "'");
             const Algorithm a = algorithm == "dstar" ? Algorithm::DStarLite : algorithm == "jps" ? Algorithm::JumpPoint : Algorithm::AStar;
             return std::make_shared<robot::GridDecider>(a, plan::heuristic_from_name(heuristic));
           }), py::arg("algorithm") = "astar",
           py::arg("heuristic") = std::string(plan::heuristic_name(plan::GridSearchOptions{}.heuristic)))
      .def_property_readonly("search_seconds", &robot::GridDecider::search_seconds, "Time spent searching so far.")
      .def_property_readonly("searches", &robot::GridDecider::searches, "Searches (plans and repairs) so far.");
  py::class_<robot::OmplDecider, robot::Decider, std::shared_ptr<robot::OmplDecider>>(m, "OmplDecider", R"doc(
Sampling-based motion planning with OMPL on the robot's map (SE2, a disc robot): RRTConnect, RRTstar,
LazyPRM, ... Each plan is bounded by `iterations` (no clock), so runs are reproducible on any
machine. Replans when the path becomes blocked.)doc")
      .def(py::init<std::string, unsigned>(), py::arg("planner") = plan::OmplOptions{}.planner,
           py::arg("iterations") = robot::OmplDecider::kDefaultIterations)
      .def_property_readonly("search_seconds", &robot::OmplDecider::search_seconds)
      .def_property_readonly("searches", &robot::OmplDecider::searches);

  py::class_<robot::OrderGenerator, Generator, std::shared_ptr<robot::OrderGenerator>>(m, "OrderGenerator", R"doc(
gObjective: eObjective<to=robot, marker> events from a timed script (schedule) and from orders given
while running (order, from any thread: they go out at the next frame).)doc")
      .def(py::init<const Alphabet&, const std::string&>(), py::arg("alphabet"), py::arg("event") = "eObjective")
      .def("schedule", &robot::OrderGenerator::schedule, py::arg("frame"), py::arg("robot"), py::arg("marker"))
      .def("order", &robot::OrderGenerator::order, py::arg("robot"), py::arg("marker"),
           py::call_guard<py::gil_scoped_release>())
      .def("cancel", &robot::OrderGenerator::cancel, py::arg("robot"), py::call_guard<py::gil_scoped_release>(),
           "Interrupt `robot`'s task at the next frame: eObjective<marker=-1> (it stops and waits for its next order).")
      .def("pending", &robot::OrderGenerator::pending, py::arg("frame"),
           "Whether orders are still to come after `frame`.")
      .def_property_readonly("given", &robot::OrderGenerator::given, "Orders sent so far.")
      .def_property_readonly("last", &robot::OrderGenerator::last,
                             "Robot -> the marker of its last order (-1: its task was interrupted).");
  py::class_<robot::ArrivalCondition, StopCondition, std::shared_ptr<robot::ArrivalCondition>>(m, "ArrivalCondition",
      "Done when orders were sent, none is still to come, and every robot sent somewhere has reached it.")
      .def(py::init<const Alphabet&, std::shared_ptr<const robot::OrderGenerator>, const std::string&>(),
           py::arg("alphabet"), py::arg("orders"), py::arg("actor") = "ARobot");

  m.def("robot_map", [](MapArg grid, bool knows_map) {
         return std::const_pointer_cast<Blob>(std::shared_ptr<const Blob>(robot::make_robot_map(grid_from_python(grid), knows_map)));
       }, py::arg("grid"), py::arg("knows_map") = true,
       "A robot's grid (an int16 vwg.Blob): the known map (walls 100, free 0, unknown -1), or all free (eq. 13).");

  m.def("add_arobot", [](Alphabet& alphabet, std::shared_ptr<robot::Decider> decider, MapArg grid, py::dict rooms,
                         double radius, double margin, double goal_tolerance, double step_length, bool carve,
                         const std::string& name, const std::vector<platform::RobotSettings>& robots,
                         const robot::AvoidanceSettings& avoidance) {
         robot::ARobotConfig config;
         config.map = geometry_of(grid);
         config.radius = radius;
         config.margin = margin;
         config.goal_tolerance = goal_tolerance;
         config.step_length = step_length;
         config.carve_free_space = carve;
         // Avoiding robots keep to the slowest robot's limits (one ARobot serves them all).
         for (std::size_t i = 0; i < robots.size(); ++i) {
           const platform::RobotLimits& l = robots[i].limits;
           platform::RobotLimits& c = config.limits;
           if (i == 0) c = l;
           c.max_speed = std::min(c.max_speed, l.max_speed), c.max_turn_rate = std::min(c.max_turn_rate, l.max_turn_rate);
           c.max_accel = std::min(c.max_accel, l.max_accel), c.max_turn_accel = std::min(c.max_turn_accel, l.max_turn_accel);
         }
         config.avoidance = avoidance;
         for (auto item : rooms) {
           py::sequence xy = item.second.cast<py::sequence>();
           config.rooms[item.first.cast<int>()] = {xy[0].cast<double>(), xy[1].cast<double>()};
         }
         const SymbolId id = alphabet.add_actor(name, robot::arobot_events(), robot::arobot_attributes(), nullptr);
         alphabet.set_behavior(id, std::make_shared<robot::ARobot>(alphabet, config, std::move(decider)));
       },
       py::arg("alphabet"), py::arg("decider"), py::arg("grid"), py::arg("rooms"), py::arg("radius") = robot::ARobotConfig{}.radius,
       py::arg("margin") = robot::ARobotConfig{}.margin, py::arg("goal_tolerance") = robot::ARobotConfig{}.goal_tolerance,
       py::arg("step_length") = robot::ARobotConfig{}.step_length, py::arg("carve") = robot::ARobotConfig{}.carve_free_space,
       py::arg("name") = "ARobot", py::arg("robots") = std::vector<platform::RobotSettings>{},
       py::arg("avoidance") = robot::AvoidanceSettings{},
       // The alphabet keeps a decider written in Python alive: its C++ part alone cannot call decide().
       py::keep_alive<1, 2>(),
       R"doc(Register the actor type ARobot (paper eq. 11) with its decider. `grid` gives the map geometry,
`rooms` the known rooms as {marker id: (x, y) goal}; `robots` the world's robots (avoiding robots keep to the
slowest one's limits) and `avoidance` the settings of those that avoid (attribute ``avoid``). The alphabet must
already have the symbols Robot, Move, Rotate (and Velocity, for robots that avoid) and the events of
arobot_event_types().)doc");
  m.def("arobot_event_types", []() {
    py::dict out;
    for (const auto& [name, schema] : robot::arobot_event_types()) out[py::str(name)] = schema_to_python(schema);
    return out;
  }, "The event types ARobot responds to, with their fields {name: (kind, default)}.");
}

}  // namespace vwg::bindings
