// Path planning in vwg._core: grid A*, D* Lite and the OMPL planners of vwg::plan. Inputs are
// checked here and in C++, and bad ones raise vwg.SchemaError naming the argument; the GIL is
// released while a search runs.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "common.hpp"
#include "vwg/plan/astar.hpp"
#include "vwg/plan/dstar_lite.hpp"
#include "vwg/plan/jps.hpp"
#include "vwg/plan/movingai.hpp"
#include "vwg/plan/ompl_planner.hpp"

namespace vwg::bindings {

namespace {

struct MaskTag {
  static constexpr auto name = py::detail::const_name("numpy.typing.NDArray[numpy.bool_]");
};
struct CellTag {
  static constexpr auto name = py::detail::const_name("tuple[int, int]");
};
struct CellsTag {
  static constexpr auto name = py::detail::const_name("collections.abc.Iterable[tuple[int, int]]");
};
struct PlanPoseTag {
  static constexpr auto name = py::detail::const_name("tuple[float, float] | tuple[float, float, float]");
};
using MaskArg = LooseArg<MaskTag>;
using CellArg = LooseArg<CellTag>;
using CellsArg = LooseArg<CellsTag>;
using PlanPoseArg = LooseArg<PlanPoseTag>;

/// What astar and DStarLite.path return: (path, length).
using PathResult = py::typing::Tuple<py::typing::Optional<py::typing::List<py::typing::Tuple<int, int>>>, float>;

}  // namespace

}  // namespace vwg::bindings



namespace vwg::bindings {

namespace {

std::string type_name(py::handle obj) { return py::str(py::type::handle_of(obj).attr("__name__")); }

/// A 2-D numpy bool array (True = blocked) as a BlockedGrid, rows and columns as in the array.
geometry::BlockedGrid blocked_from_python(py::handle obj, const char* field) {
  if (!py::isinstance<py::array>(obj)) {
    throw SchemaError(field, "expected a 2-D numpy array of bool (True = blocked), got " + type_name(obj));
  }
  const auto array = py::reinterpret_borrow<py::array>(obj);
  if (array.ndim() != 2) {
    throw SchemaError(field, "expected a 2-D array (rows × columns), got " + std::to_string(array.ndim()) +
                                 " dimensions");
  }
  if (!array.dtype().is(py::dtype::of<bool>())) {
    throw SchemaError(field, "expected an array of dtype bool (True = blocked), got " +
                                 std::string(py::str(array.dtype())) +
                                 "; make one with a comparison such as `grid.data >= 50`, or `.astype(bool)`");
  }
  const auto rows = array.shape(0), cols = array.shape(1);
  if (rows > std::numeric_limits<int>::max() || cols > std::numeric_limits<int>::max()) {
    throw SchemaError(field, "array too large");
  }
  const auto typed = py::reinterpret_borrow<py::array_t<bool>>(array);
  if (typed.flags() & py::array::c_style) {
    return geometry::BlockedGrid::from_mask(std::span<const bool>(typed.data(), static_cast<std::size_t>(rows * cols)),
                                        static_cast<int>(rows), static_cast<int>(cols));
  }
  // A strided view (say blocked[::-1]): read it element by element.
  geometry::BlockedGrid grid(static_cast<int>(rows), static_cast<int>(cols));
  const auto view = typed.unchecked<2>();
  for (py::ssize_t r = 0; r < rows; ++r) {
    for (py::ssize_t c = 0; c < cols; ++c) {
      if (view(r, c)) grid.set_blocked({static_cast<int>(r), static_cast<int>(c)}, true);
    }
  }
  return grid;
}

/// An integer from Python (int, numpy integer, anything with __index__), else SchemaError(field).
long long integer_from_python(py::handle obj, const std::string& field, const char* what) {
  if (py::isinstance<py::bool_>(obj) || !PyIndex_Check(obj.ptr())) {
    throw SchemaError(field, std::string("expected ") + what + ", got " + type_name(obj));
  }
  const long long v = PyLong_AsLongLong(py::reinterpret_steal<py::object>(PyNumber_Index(obj.ptr())).ptr());
  if (v == -1 && PyErr_Occurred()) {
    PyErr_Clear();
    throw SchemaError(field, std::string("expected ") + what + ", got an integer out of range");
  }
  return v;
}

/// A real number from Python (int, float, numpy scalar), else SchemaError(field).
double real_from_python(py::handle obj, const std::string& field) {
  if (py::isinstance<py::bool_>(obj) || py::isinstance<py::str>(obj) || !PyNumber_Check(obj.ptr())) {
    throw SchemaError(field, "expected a number, got " + type_name(obj));
  }
  const double v = PyFloat_AsDouble(obj.ptr());
  if (v == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();
    throw SchemaError(field, "expected a number, got " + type_name(obj));
  }
  return v;
}

/// A sequence of numbers (tuple, list, 1-D array) of one of the lengths allowed.
std::vector<py::object> items_of(py::handle obj, const std::string& field, std::size_t min_size, std::size_t max_size,
                                 const char* what) {
  if (py::isinstance<py::str>(obj) || py::isinstance<py::bytes>(obj) || !py::isinstance<py::sequence>(obj)) {
    if (!py::isinstance<py::array>(obj)) {
      throw SchemaError(field, std::string("expected ") + what + ", got " + type_name(obj));
    }
  }
  std::vector<py::object> items;
  for (py::handle item : py::iter(obj)) items.push_back(py::reinterpret_borrow<py::object>(item));
  if (items.size() < min_size || items.size() > max_size) {
    throw SchemaError(field, std::string("expected ") + what + ", got " + std::to_string(items.size()) + " values");
  }
  return items;
}

geometry::Cell cell_from_python(py::handle obj, const std::string& field) {
  const auto items = items_of(obj, field, 2, 2, "a (row, col) pair of integers");
  const long long row = integer_from_python(items[0], field, "a (row, col) pair of integers");
  const long long col = integer_from_python(items[1], field, "a (row, col) pair of integers");
  // Anything beyond int is outside every grid; clamping keeps the "outside the grid" message.
  auto clamp = [](long long v) { return static_cast<int>(std::clamp<long long>(v, -1, std::numeric_limits<int>::max())); };
  return {clamp(row), clamp(col)};
}

/// (x, y) or (x, y, yaw): a pose, or a point facing +x (the physics binding's pose_from_python takes (x, y, yaw) only).
geometry::Pose2 pose_or_point_from_python(py::handle obj, const std::string& field) {
  const auto items = items_of(obj, field, 2, 3, "(x, y) or (x, y, yaw) in metres and radians");
  geometry::Pose2 p;
  p.x = real_from_python(items[0], field);
  p.y = real_from_python(items[1], field);
  p.theta = items.size() == 3 ? real_from_python(items[2], field) : 0.0;
  return p;
}

plan::GridSearchOptions options_from_python(bool diagonal, bool corner_cutting, const std::string& heuristic) {
  plan::GridSearchOptions o;
  o.diagonal = diagonal;
  o.corner_cutting = corner_cutting;
  o.heuristic = plan::heuristic_from_name(heuristic);
  plan::validate(o);
  return o;
}

/// (path, length): a list of (row, col) tuples and a float, or (None, inf). Built with the C API:
/// pybind11's make_tuple per cell, a new int per row and column, and the collections of the cyclic
/// GC that thousands of new tuples set off took a sixth of a long search's time (a maze's
/// 5,800-cell paths). A path's cells share few rows and columns: each int is made once.
PathResult path_to_python(const plan::GridPath& p) {
  if (!p.found()) return py::reinterpret_steal<PathResult>(py::make_tuple(py::none(), p.length).release());
  int largest = 0;
  for (const geometry::Cell& c : p.cells) largest = std::max({largest, c.row, c.col});
  std::vector<py::object> ints(static_cast<std::size_t>(largest) + 1);
  auto int_of = [&](int v) {
    py::object& i = ints[static_cast<std::size_t>(v)];
    if (!i) i = py::int_(v);
    return i.inc_ref().ptr();
  };
  py::list cells(p.cells.size());
  for (std::size_t i = 0; i < p.cells.size(); ++i) {
    PyObject* cell = PyTuple_New(2);
    if (cell == nullptr) throw py::error_already_set();
    PyList_SET_ITEM(cells.ptr(), static_cast<Py_ssize_t>(i), cell);  // the list owns it from here
    PyTuple_SET_ITEM(cell, 0, int_of(p.cells[i].row));
    PyTuple_SET_ITEM(cell, 1, int_of(p.cells[i].col));
    // Two ints make no cycle: untracked, as the collector would leave it after its first look.
    PyObject_GC_UnTrack(cell);
  }
  return py::reinterpret_steal<PathResult>(py::make_tuple(std::move(cells), p.length).release());
}

/// A D* Lite planner with a lock: the GIL is released during its searches, so two Python threads
/// could otherwise use one planner at once.
struct DStarLiteHandle {
  explicit DStarLiteHandle(plan::DStarLite p) : planner(std::move(p)) {}
  plan::DStarLite planner;
  std::mutex mutex;
};

plan::OmplOptions ompl_options(const std::string& planner, py::handle time_limit, py::handle seed, bool simplify,
                               const std::optional<RealArg>& spacing, py::handle iterations) {
  plan::OmplOptions o;
  o.planner = planner;
  o.time_limit = real_from_python(time_limit, "time_limit");
  const long long s = integer_from_python(seed, "seed", "an integer from 0 to 2**32 - 1");
  if (s < 0 || s > 0xFFFFFFFFLL) throw SchemaError("seed", "expected an integer from 0 to 2**32 - 1");
  o.seed = static_cast<std::uint32_t>(s);
  o.simplify = simplify;
  if (spacing) o.spacing = real_from_python(*spacing, "spacing");
  const long long n = integer_from_python(iterations, "iterations", "a non-negative integer");
  if (n < 0 || n > 0xFFFFFFFFLL) throw SchemaError("iterations", "expected a non-negative integer");
  o.iterations = static_cast<unsigned>(n);
  return o;
}

const char* kAstarDoc = R"doc(Shortest path on a grid by A*.

blocked: 2-D numpy bool array, True = blocked (any row order: the search is on (row, col) indices).
start, goal: (row, col). diagonal: 8-connected (else 4); corner_cutting: a diagonal move may pass a
blocked orthogonal neighbour; heuristic: "euclidean" (default, as in the paper), "octile",
"manhattan" (4-connected only) or "zero". Straight moves cost 1, diagonal moves √2.

Returns (path, length): path a list of (row, col) tuples from start to goal inclusive, length a
float; (None, inf) when there is no path (a blocked goal has none). Raises vwg.SchemaError naming
the argument for a start or goal outside the grid, a blocked start, or a mask that is not 2-D bool.)doc";

}  // namespace

void init_plan(py::module_& m) {
  const std::string kDefaultHeuristic(plan::heuristic_name(plan::GridSearchOptions{}.heuristic));
  m.def(
      "astar",
      [](MaskArg blocked, CellArg start, CellArg goal, bool diagonal, bool corner_cutting,
         const std::string& heuristic) {
        const geometry::BlockedGrid grid = blocked_from_python(blocked, "blocked");
        const geometry::Cell s = cell_from_python(start, "start"), g = cell_from_python(goal, "goal");
        const plan::GridSearchOptions o = options_from_python(diagonal, corner_cutting, heuristic);
        plan::GridPath p;
        {
          py::gil_scoped_release release;
          // One work area per thread, kept between calls: setting one up for a 512 × 512 map costs a
          // good part of a search (it holds about 18 bytes per cell until the thread ends).
          thread_local plan::AStar search;
          p = search.search(grid, s, g, o);
        }
        return path_to_python(p);
      },
      py::arg("blocked"), py::arg("start"), py::arg("goal"), py::arg("diagonal") = plan::GridSearchOptions{}.diagonal,
      py::arg("corner_cutting") = plan::GridSearchOptions{}.corner_cutting, py::arg("heuristic") = kDefaultHeuristic, kAstarDoc);

  m.def(
      "jps",
      [](MaskArg blocked, CellArg start, CellArg goal, const std::string& heuristic) {
        const geometry::BlockedGrid grid = blocked_from_python(blocked, "blocked");
        const geometry::Cell s = cell_from_python(start, "start"), g = cell_from_python(goal, "goal");
        const plan::GridSearchOptions o = options_from_python(true, false, heuristic);
        plan::GridPath p;
        {
          py::gil_scoped_release release;
          thread_local plan::JumpPointSearch search;  // as astar's: one work area per thread
          p = search.search(grid, s, g, o);
        }
        return path_to_python(p);
      },
      py::arg("blocked"), py::arg("start"), py::arg("goal"), py::arg("heuristic") = kDefaultHeuristic,
      R"doc(Shortest path on a grid by Jump Point Search (Harabor & Grastien 2011).

The same problem and answer lengths as vwg.plan.astar with 8-connected moves and no corner cutting
(straight moves cost 1, diagonal √2), found by expanding only the cells where a shortest path may
turn: on open maps far fewer than A*. Returns (path, length) like astar, every cell of the path
listed; (None, inf) when there is none.)doc");

  py::class_<DStarLiteHandle>(m, "DStarLite", R"doc(Incremental shortest paths (D* Lite, Koenig & Likhachev 2002).

Same grid, moves and costs as vwg.astar; path() always has A*'s length from the current start, but
after cells change or the robot moves it repairs its previous search instead of starting again.

    planner = vwg.DStarLite(blocked, start, goal)
    path, length = planner.path()
    planner.move_to(path[1])                      # the robot took a step
    planner.update_cells([(5, 7), (5, 8)], True)  # it saw new obstacles
    path, length = planner.path()
)doc")
      .def(py::init([](MaskArg blocked, CellArg start, CellArg goal, bool diagonal, bool corner_cutting,
                       const std::string& heuristic) {
             geometry::BlockedGrid grid = blocked_from_python(blocked, "blocked");
             const geometry::Cell s = cell_from_python(start, "start"), g = cell_from_python(goal, "goal");
             const plan::GridSearchOptions o = options_from_python(diagonal, corner_cutting, heuristic);
             return std::make_unique<DStarLiteHandle>(plan::DStarLite(std::move(grid), s, g, o));
           }),
           py::arg("blocked"), py::arg("start"), py::arg("goal"), py::arg("diagonal") = plan::GridSearchOptions{}.diagonal,
           py::arg("corner_cutting") = plan::GridSearchOptions{}.corner_cutting, py::arg("heuristic") = kDefaultHeuristic)
      .def(
          "path",
          [](DStarLiteHandle& self) {
            plan::GridPath p;
            {
              py::gil_scoped_release release;
              const std::lock_guard<std::mutex> lock(self.mutex);
              p = self.planner.path();
            }
            return path_to_python(p);
          },
          "(path, length) from the current start to the goal, as vwg.astar returns them; (None, inf) if none.")
      .def(
          "update_cells",
          [](DStarLiteHandle& self, CellsArg cells, bool blocked) {
            std::vector<geometry::Cell> list;
            if (py::isinstance<py::str>(cells) || !py::hasattr(cells, "__iter__")) {
              throw SchemaError("cells", "expected an iterable of (row, col) pairs, got " + type_name(cells));
            }
            for (py::handle c : py::iter(cells)) list.push_back(cell_from_python(c, "cells"));
            py::gil_scoped_release release;
            const std::lock_guard<std::mutex> lock(self.mutex);
            self.planner.update_cells(list, blocked);
          },
          py::arg("cells"), py::arg("blocked") = true,
          "Cells (an iterable of (row, col), or an N×2 integer array) became blocked (or free, blocked=False).")
      .def(
          "move_to",
          [](DStarLiteHandle& self, CellArg cell) {
            const geometry::Cell c = cell_from_python(cell, "cell");
            const std::lock_guard<std::mutex> lock(self.mutex);
            self.planner.move_to(c);
          },
          py::arg("cell"), "The robot is now at this free (row, col) cell; the next path() starts there.")
      .def_property_readonly(
          "start",
          [](DStarLiteHandle& self) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            return std::make_tuple(self.planner.start().row, self.planner.start().col);
          },
          "The robot's cell (row, col): where path() starts.")
      .def_property_readonly(
          "goal",
          [](DStarLiteHandle& self) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            return std::make_tuple(self.planner.goal().row, self.planner.goal().col);
          },
          "The goal cell (row, col).")
      .def_property_readonly(
          "expanded",
          [](DStarLiteHandle& self) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            return self.planner.expanded();
          },
          "Vertex expansions since construction: the work the searches did.");

  py::class_<plan::OmplPlan>(m, "OmplPlan", "The outcome of an OMPL plan (vwg.plan_ompl, OmplPlanner.plan).")
      .def_readonly("solved", &plan::OmplPlan::solved, "Whether the goal pose was reached.")
      .def_readonly("status", &plan::OmplPlan::status,
                    "\"exact solution\", or why not: \"timeout\", \"approximate solution\", \"invalid goal: ...\".")
      .def_property_readonly(
          "waypoints",
          [](const plan::OmplPlan& p) {
            py::array_t<double> out({static_cast<py::ssize_t>(p.waypoints.size()), py::ssize_t{3}});
            auto w = out.mutable_unchecked<2>();
            for (std::size_t i = 0; i < p.waypoints.size(); ++i) {
              const auto r = static_cast<py::ssize_t>(i);
              w(r, 0) = p.waypoints[i].x;
              w(r, 1) = p.waypoints[i].y;
              w(r, 2) = p.waypoints[i].theta;
            }
            return out;
          },
          "N×3 float array of (x, y, yaw) from start to goal in the world frame; 0×3 on failure.")
      .def_readonly("length", &plan::OmplPlan::length, "Metres travelled in x-y; inf on failure.")
      .def_readonly("plan_time", &plan::OmplPlan::plan_time, "Seconds the planner ran.")
      .def_readonly("simplify_time", &plan::OmplPlan::simplify_time, "Seconds spent shortening the path.")
      .def_readonly("planner", &plan::OmplPlan::planner)
      .def("__bool__", [](const plan::OmplPlan& p) { return p.solved; })
      .def("__repr__", [](const plan::OmplPlan& p) {
        return "OmplPlan(planner=" + p.planner + ", status='" + p.status + "', waypoints=" +
               std::to_string(p.waypoints.size()) + ", length=" + std::to_string(p.length) + ")";
      });

  py::class_<plan::OmplGridPlanner>(m, "OmplPlanner", R"doc(OMPL planners for a disc robot on a map, reusable.

blocked: 2-D numpy bool array, True = blocked, row 0 the BOTTOM row (smallest y) as in
vwg.OccupancyGrid (flip an image-ordered mask with mask[::-1]); resolution: metres per cell; origin:
(x, y) or (x, y, yaw) of the lower-left corner of cell (0, 0) in the world frame; robot_radius: metres.
A pose is valid when the robot's disc stays strictly clear of blocked cells and inside the map;
motions are checked exactly (no sampling), so paths never cross or graze an obstacle.)doc")
      .def(py::init([](MaskArg blocked, RealArg resolution, PlanPoseArg origin, RealArg robot_radius) {
             geometry::BlockedGrid grid = blocked_from_python(blocked, "blocked");
             const double res = real_from_python(resolution, "resolution");
             const geometry::Pose2 o = pose_or_point_from_python(origin, "origin");
             const double radius = real_from_python(robot_radius, "robot_radius");
             py::gil_scoped_release release;  // the distance transform is a pass over the map
             return std::make_unique<plan::OmplGridPlanner>(std::move(grid), res, o, radius);
           }),
           py::arg("blocked"), py::arg("resolution"), py::arg("origin"), py::arg("robot_radius"))
      .def(
          "plan",
          [](const plan::OmplGridPlanner& self, PlanPoseArg start_pose, PlanPoseArg goal_pose, const std::string& planner,
             RealArg time_limit, IntArg seed, bool simplify, std::optional<RealArg> spacing, IntArg iterations) {
            const geometry::Pose2 s = pose_or_point_from_python(start_pose, "start_pose");
            const geometry::Pose2 g = pose_or_point_from_python(goal_pose, "goal_pose");
            const plan::OmplOptions o = ompl_options(planner, time_limit, seed, simplify, spacing, iterations);
            py::gil_scoped_release release;
            return self.plan(s, g, o);
          },
          py::arg("start_pose"), py::arg("goal_pose"), py::arg("planner") = plan::OmplOptions{}.planner,
          py::arg("time_limit") = plan::OmplOptions{}.time_limit,
          py::arg("seed") = plan::OmplOptions{}.seed, py::kw_only(), py::arg("simplify") = plan::OmplOptions{}.simplify, py::arg("spacing") = py::none(),
          py::arg("iterations") = plan::OmplOptions{}.iterations,
          "Plan from start_pose to goal_pose ((x, y) or (x, y, yaw)); see vwg.plan_ompl for the options.")
      .def("valid", &plan::OmplGridPlanner::valid, py::arg("x"), py::arg("y"), "Whether the robot fits at (x, y).")
      .def("motion_valid", &plan::OmplGridPlanner::motion_valid, py::arg("x0"), py::arg("y0"), py::arg("x1"),
           py::arg("y1"), "Whether the robot can move straight from (x0, y0) to (x1, y1).")
      .def("clearance", &plan::OmplGridPlanner::clearance, py::arg("x"), py::arg("y"), py::arg("cap") = plan::OmplGridPlanner::kDefaultClearanceCap,
           "Metres from (x, y) to the nearest obstacle or map edge, at most cap.")
      .def_property_readonly("robot_radius", &plan::OmplGridPlanner::robot_radius)
      .def_property_readonly("resolution", &plan::OmplGridPlanner::resolution)
      .def_static("planners", &plan::OmplGridPlanner::planner_names, "The planner names plan() accepts.");

  m.def(
      "plan_ompl",
      [](MaskArg blocked, RealArg resolution, PlanPoseArg origin, PlanPoseArg start_pose, PlanPoseArg goal_pose,
         RealArg robot_radius, const std::string& planner, RealArg time_limit, IntArg seed, bool simplify,
         std::optional<RealArg> spacing, IntArg iterations) {
        geometry::BlockedGrid grid = blocked_from_python(blocked, "blocked");
        const double res = real_from_python(resolution, "resolution");
        const geometry::Pose2 o = pose_or_point_from_python(origin, "origin");
        const geometry::Pose2 s = pose_or_point_from_python(start_pose, "start_pose");
        const geometry::Pose2 g = pose_or_point_from_python(goal_pose, "goal_pose");
        const double radius = real_from_python(robot_radius, "robot_radius");
        const plan::OmplOptions opts = ompl_options(planner, time_limit, seed, simplify, spacing, iterations);
        py::gil_scoped_release release;
        return plan::plan_ompl(grid, res, o, s, g, radius, opts);
      },
      py::arg("blocked"), py::arg("resolution"), py::arg("origin"), py::arg("start_pose"), py::arg("goal_pose"),
      py::arg("robot_radius"), py::arg("planner") = plan::OmplOptions{}.planner,
          py::arg("time_limit") = plan::OmplOptions{}.time_limit, py::arg("seed") = plan::OmplOptions{}.seed,
      py::kw_only(), py::arg("simplify") = plan::OmplOptions{}.simplify, py::arg("spacing") = py::none(),
      py::arg("iterations") = plan::OmplOptions{}.iterations,
      R"doc(Plan a path for a disc robot with an OMPL planner, in SE(2).

blocked: 2-D numpy bool array, True = blocked, row 0 the BOTTOM row (smallest y) as in vwg.OccupancyGrid;
resolution: metres per cell; origin: (x, y[, yaw]) of the lower-left corner of cell (0, 0);
start_pose, goal_pose: (x, y[, yaw]) in the world frame; robot_radius: metres.
planner: an OMPL geometric planner by name ("RRTConnect", "RRT", "RRTstar", "PRM", ...: see
vwg.OmplPlanner.planners()); time_limit: seconds (anytime planners such as RRT* use all of it);
seed: OMPL's random seed, so plans repeat (for planners that stop by themselves; PRM does not repeat);
simplify: shorten the path; spacing: metres between returned waypoints (None: one cell, 0: vertices only);
iterations: also stop after this many planner iterations (makes RRT* and the like repeatable).

Returns a vwg.OmplPlan: solved, status, waypoints (N×3: x, y, yaw), length (metres, x-y), plan_time.
A failure (no path in time, goal in collision) is a plan with solved False, no waypoints and length
inf. Raises vwg.SchemaError for a start pose off the map or in collision, an unknown planner or a bad
argument. Each call computes the map's distance transform: reuse a vwg.OmplPlanner to plan many times.)doc");

  // --- the MovingAI benchmark formats: the one reader (vwg.io.maps.load_movingai and the benchmarks call it) ---
  py::class_<plan::MovingAiScenario>(m, "MovingAiScenario", "One line of a MovingAI `.map.scen` file.")
      .def_readonly("bucket", &plan::MovingAiScenario::bucket)
      .def_readonly("map", &plan::MovingAiScenario::map, "The map's path as written in the file.")
      .def_readonly("map_width", &plan::MovingAiScenario::map_width)
      .def_readonly("map_height", &plan::MovingAiScenario::map_height)
      .def_property_readonly("start_x", [](const plan::MovingAiScenario& s) { return s.start.col; }, "MovingAI x: the column.")
      .def_property_readonly("start_y", [](const plan::MovingAiScenario& s) { return s.start.row; }, "MovingAI y: the row from the top.")
      .def_property_readonly("goal_x", [](const plan::MovingAiScenario& s) { return s.goal.col; })
      .def_property_readonly("goal_y", [](const plan::MovingAiScenario& s) { return s.goal.row; })
      .def_readonly("optimal_length", &plan::MovingAiScenario::optimal_length,
                    "The published optimal length: 8-connected, no corner cutting, to about 6 significant digits.")
      .def("__repr__", [](const plan::MovingAiScenario& s) {
        return "MovingAiScenario(" + s.map + ", (" + std::to_string(s.start.col) + ", " + std::to_string(s.start.row) +
               ") -> (" + std::to_string(s.goal.col) + ", " + std::to_string(s.goal.row) + "), " + format_real(s.optimal_length) + ")";
      });
  m.def(
      "movingai_grid",
      [](const py::bytes& text, const std::string& source, double resolution, PoseArg origin) {
        char* data = nullptr;
        Py_ssize_t size = 0;
        if (PyBytes_AsStringAndSize(text.ptr(), &data, &size) != 0) throw py::error_already_set();
        geometry::OccupancyGrid grid;
        const geometry::Pose2 o = pose_or_point_from_python(origin, "origin");
        {
          py::gil_scoped_release release;
          grid = plan::to_occupancy_grid(plan::parse_movingai_map({data, static_cast<std::size_t>(size)}, source), resolution, o);
        }
        geometry::check_grid(grid, "OccupancyGrid");
        return grid;
      },
      py::arg("text"), py::arg("source"), py::arg("resolution"), py::arg("origin"),
      "The occupancy grid (0 free, 100 blocked, row 0 the bottom row) of the text of a MovingAI `.map` file, placed "
      "by `resolution` and `origin` (the format has neither). Characters other than . G S (passable) and @ O T W "
      "(blocked) are refused: vwg.WorldFileError naming `source`, the line, the column and the field.");
  m.def(
      "movingai_scenarios",
      [](const py::bytes& text, const std::string& source) {
        char* data = nullptr;
        Py_ssize_t size = 0;
        if (PyBytes_AsStringAndSize(text.ptr(), &data, &size) != 0) throw py::error_already_set();
        return plan::parse_movingai_scenarios({data, static_cast<std::size_t>(size)}, source);
      },
      py::arg("text"), py::arg("source"),
      "The scenarios of the text of a MovingAI `.map.scen` file (vwg.WorldFileError naming `source` and the line).");
}

}  // namespace vwg::bindings
