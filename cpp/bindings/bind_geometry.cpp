// The geometry library in vwg._core: the occupancy grid itself (vwg.io.maps.OccupancyGrid is this class
// with a file's mode and source added), its cell <-> world transforms and masks, and clearance and
// inflation, so that Python answers with the same code as the robots, planners and simulator.
#include <cstdint>
#include <string>

#include "common.hpp"
#include "sim_convert.hpp"
#include "geometry/clearance.hpp"
#include "geometry/inflate.hpp"
#include "vwg/geometry/occupancy_grid.hpp"

namespace vwg::bindings {

namespace {

using geometry::OccupancyGrid;

constexpr const char* kOwner = "OccupancyGrid";

struct GridDataTag {
  static constexpr auto name = py::detail::const_name("numpy.typing.ArrayLike");
};
struct OriginTag {
  static constexpr auto name = py::detail::const_name("collections.abc.Sequence[float]");
};

/// The cells of a 2-D array of integers (-1..100; int8 taken as it is) or bools (True = 100), copied.
void set_cells(OccupancyGrid& g, py::handle data) {
  py::object np = py::module_::import("numpy");
  py::array a = np.attr("asarray")(data);
  const std::string field = std::string(kOwner) + ".data";
  if (a.ndim() != 2 || a.shape(0) == 0 || a.shape(1) == 0) {
    throw SchemaError(field, "expected a non-empty 2-D array, got shape " + std::string(py::str(a.attr("shape"))));
  }
  const char kind = a.dtype().kind();
  if (kind == 'b') {
    a = np.attr("where")(a, geometry::kOccupied, geometry::kFree).attr("astype")(np.attr("int8"));
  } else if (!a.dtype().is(py::dtype::of<std::int8_t>())) {
    if (kind != 'i' && kind != 'u') throw SchemaError(field, "expected integers, got " + std::string(py::str(a.dtype())));
    if (a.attr("min")().cast<py::int_>() < py::int_(-1) || a.attr("max")().cast<py::int_>() > py::int_(100)) {
      throw SchemaError(field, "values must be -1 (unknown) or 0..100");
    }
    a = a.attr("astype")(np.attr("int8"));
  }
  auto cells = py::array_t<std::int8_t, py::array::c_style | py::array::forcecast>::ensure(a);
  g.height = static_cast<int>(cells.shape(0));
  g.width = static_cast<int>(cells.shape(1));
  g.data.assign(cells.data(), cells.data() + cells.size());
}

/// A row or column number as Python gives it (any int): whether it is within [0, size).
bool index_within(py::handle i, int size) {
  py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(i.ptr()));
  if (!index) throw py::error_already_set();
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  return overflow == 0 && v >= 0 && v < size;
}

/// A numpy bool mask of the grid's cells, row 0 the bottom row.
template <class Rule>
py::array_t<bool> mask(const OccupancyGrid& g, Rule rule) {
  py::array_t<bool> out({g.height, g.width});
  bool* dst = out.mutable_data();
  for (std::size_t i = 0; i < g.data.size(); ++i) dst[i] = rule(g.data[i]);
  return out;
}

}  // namespace

void init_geometry(py::module_& m) {
  m.attr("OBSTACLE_THRESHOLD") = geometry::kObstacleThreshold;
  const OccupancyGrid defaults{};
  py::class_<OccupancyGrid>(m, "OccupancyGrid", R"doc(
A 2-D occupancy grid in nav_msgs/OccupancyGrid order (row 0 = the bottom row, smallest y): the C++
vwg::geometry::OccupancyGrid the simulator, the planners and the robots use. `data` is an int8 view
(rows × columns) of its cells, -1 unknown / 0 free / 100 occupied (1..99 in "scale" maps), that keeps
the grid alive and writes through to it; `resolution` is metres per cell; `origin` the (x, y, yaw)
pose of the lower-left corner of cell (0, 0), as map_server's `origin`. The cells are copied in.)doc")
      .def(py::init([](const LooseArg<GridDataTag>& data, double resolution, const LooseArg<OriginTag>& origin) {
             OccupancyGrid g;
             set_cells(g, data);
             g.resolution = resolution;
             g.origin = pose_from_python(origin, std::string(kOwner) + ".origin");
             geometry::check_grid(g, kOwner);
             return g;
           }),
           py::arg("data"), py::arg("resolution"), py::arg("origin") = pose_to_python(defaults.origin))
      .def(py::init([](const OccupancyGrid& other) { return OccupancyGrid(other); }), py::arg("grid"), "A copy.")
      .def_property_readonly(
          "data",
          [](py::object self) {
            auto& g = self.cast<OccupancyGrid&>();
            return py::array_t<std::int8_t>({static_cast<py::ssize_t>(g.height), static_cast<py::ssize_t>(g.width)},
                                            {static_cast<py::ssize_t>(g.width), static_cast<py::ssize_t>(1)}, g.data.data(), self);
          },
          "The cells, rows × columns int8, row 0 the bottom row: a view of the grid (writes change it).")
      .def_property_readonly("width", [](const OccupancyGrid& g) { return g.width; }, "Number of columns.")
      .def_property_readonly("height", [](const OccupancyGrid& g) { return g.height; }, "Number of rows.")
      .def_property_readonly("resolution", [](const OccupancyGrid& g) { return g.resolution; }, "Metres per cell.")
      .def_property_readonly("origin", [](const OccupancyGrid& g) { return std::make_tuple(g.origin.x, g.origin.y, g.origin.theta); },
                             "(x, y, yaw) of the lower-left corner of cell (0, 0).")
      .def_property_readonly("width_m", &OccupancyGrid::width_m, "Width of the map in metres.")
      .def_property_readonly("height_m", &OccupancyGrid::height_m, "Height of the map in metres.")
      .def("world_to_grid", [](const OccupancyGrid& g, double x, double y) {
        double u, v;
        g.world_to_grid(x, y, u, v);
        return std::make_tuple(u, v);
      }, py::arg("x"), py::arg("y"), "Continuous grid coordinates (u along columns, v along rows, in cells) of the world point (x, y).")
      .def("grid_to_world", [](const OccupancyGrid& g, double u, double v) {
        double x, y;
        g.grid_to_world(u, v, x, y);
        return std::make_tuple(x, y);
      }, py::arg("u"), py::arg("v"), "World point of the continuous grid coordinates (u, v) (cells).")
      .def("world_to_cell", [](const OccupancyGrid& g, double x, double y) {
        std::int64_t row, col;
        g.world_to_cell(x, y, row, col);
        return std::make_tuple(row, col);
      }, py::arg("x"), py::arg("y"),
         "(row, col) of the cell holding the world point (x, y); may lie outside the grid (see `inside`). A point "
         "whose cell number is beyond ±2**62 (or not finite) gets ±2**62.")
      .def("cell_to_world", [](const OccupancyGrid& g, double row, double col) {
        double x, y;
        g.cell_to_world(row, col, x, y);
        return std::make_tuple(x, y);
      }, py::arg("row"), py::arg("col"), "World (x, y) of the centre of cell (row, col).")
      .def("inside", [](const OccupancyGrid& g, const IntArg& row, const IntArg& col) {
        return index_within(row, g.height) && index_within(col, g.width);
      }, py::arg("row"), py::arg("col"), "Whether (row, col) is a cell of the grid.")
      .def("contains", &OccupancyGrid::contains, py::arg("x"), py::arg("y"), "Whether the world point (x, y) lies on the map.")
      .def("blocked", [](const OccupancyGrid& g, int threshold, bool unknown) {
        return mask(g, [&](std::int8_t v) { return geometry::blocked_value(v, threshold, unknown); });
      }, py::arg("threshold") = geometry::kObstacleThreshold, py::arg("unknown") = false,
         "Boolean mask of obstacle cells: value >= threshold (and unknown cells when `unknown`). The default counts "
         "unknown cells as not blocked, as the simulator does; planners and checks that must stay in known space pass "
         "unknown=True.")
      .def("free_mask", [](const OccupancyGrid& g, int threshold) {
        return mask(g, [&](std::int8_t v) { return v >= 0 && !geometry::blocked_value(v, threshold, false); });
      }, py::arg("threshold") = geometry::kObstacleThreshold, "Boolean mask of known cells below the threshold (0 in a trinary map).")
      .def("__eq__", [](const OccupancyGrid& a, py::handle other) -> py::object {
        if (!py::isinstance<OccupancyGrid>(other)) return py::reinterpret_borrow<py::object>(Py_NotImplemented);
        const auto& b = other.cast<const OccupancyGrid&>();
        return py::bool_(a.resolution == b.resolution && a.origin.x == b.origin.x && a.origin.y == b.origin.y &&
                         a.origin.theta == b.origin.theta && a.width == b.width && a.height == b.height && a.data == b.data);
      }, py::is_operator(), "Same cells, resolution and origin.")
      .def("__repr__", [](const OccupancyGrid& g) {
        return "vwg._core.OccupancyGrid(" + std::to_string(g.width) + "×" + std::to_string(g.height) + " cells, " +
               format_real(g.resolution) + " m/cell)";
      })
      .def(py::pickle(
          [](const OccupancyGrid& g) {
            py::array_t<std::int8_t> cells({g.height, g.width}, g.data.data());  // a copy: no base
            return py::make_tuple(cells, g.resolution, std::make_tuple(g.origin.x, g.origin.y, g.origin.theta));
          },
          [](const py::tuple& t) {
            OccupancyGrid g;
            set_cells(g, t[0]);
            g.resolution = t[1].cast<double>();
            g.origin = pose_from_python(t[2], std::string(kOwner) + ".origin");
            geometry::check_grid(g, kOwner);
            return g;
          }));

  m.def(
      "grid_clearance",
      [](MapArg grid, double x, double y, double limit, int threshold, bool unknown) {
        return geometry::clearance(grid_from_python(grid), x, y, limit, threshold, unknown);
      },
      py::arg("grid"), py::arg("x"), py::arg("y"), py::arg("limit"), py::arg("threshold") = geometry::kObstacleThreshold,
      py::arg("unknown") = true,
      "Distance (m) from the world point (x, y) to the nearest cell of value >= threshold (and unknown cells and "
      "everything off the grid when `unknown`), capped at `limit`; 0 inside one.");
  m.def(
      "grid_inflate",
      [](MapArg grid, double radius, int threshold, bool unknown) {
        const geometry::OccupancyGrid g = grid_from_python(grid);
        const geometry::BlockedGrid out =
            geometry::inflate(geometry::BlockedGrid::from_occupancy(g, threshold, unknown), radius / g.resolution, unknown);
        py::array_t<bool> mask({g.height, g.width});
        auto cells = mask.mutable_unchecked<2>();
        for (int r = 0; r < g.height; ++r) {
          for (int c = 0; c < g.width; ++c) cells(r, c) = out.blocked({r, c});
        }
        return mask;
      },
      py::arg("grid"), py::arg("radius"), py::arg("threshold") = geometry::kObstacleThreshold, py::arg("unknown") = true,
      "Boolean mask of the cells whose centre is within `radius` metres (inclusive) of a cell of value >= threshold "
      "(and of unknown cells and the grid's edge when `unknown`): where a disc robot's centre may not be.");
}

}  // namespace vwg::bindings
