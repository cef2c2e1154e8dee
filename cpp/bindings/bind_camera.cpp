// The robot camera and the 3D overview in Python: vwg._core.CameraRenderer, render_overview and
// OverviewCamera (vwg/sim/camera.hpp, vwg/sim/overview3d.hpp).
//
// Threads: rendering releases the GIL. A CameraRenderer keeps buffers and a noise generator, so
// its renders take turns (a mutex); separate renderers render in parallel.
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "common.hpp"
#include "sim_convert.hpp"
#include "vwg/sim/camera.hpp"
#include "vwg/sim/overview3d.hpp"

namespace vwg::bindings {

namespace {

/// A field of a description: a dict key or an attribute; None when it has neither.
py::object field_of(py::handle obj, const char* name) {
  if (py::isinstance<py::dict>(obj)) {
    const auto d = py::reinterpret_borrow<py::dict>(obj);
    return d.contains(name) ? py::object(d[name]) : py::object(py::none());
  }
  return py::hasattr(obj, name) ? py::object(obj.attr(name)) : py::object(py::none());
}

double finite_number(py::handle value, const std::string& field) {
  double v;
  try {
    v = value.cast<double>();
  } catch (const py::cast_error&) {
    throw SchemaError(field, "expected a number, got " + std::string(py::str(py::type::handle_of(value).attr("__name__"))));
  }
  if (!std::isfinite(v)) throw SchemaError(field, "expected a finite number");
  return v;
}

int integer(py::handle value, const std::string& field) {
  if (!py::isinstance<py::int_>(value) || py::isinstance<py::bool_>(value)) {
    throw SchemaError(field, "expected an integer, got " + std::string(py::str(py::type::handle_of(value).attr("__name__"))));
  }
  return value.cast<int>();
}

/// A marker from a dict or an object (vwg.robotworld.Room): id or marker; x and y, or at = (x, y);
/// facing; optional size, height, and label or name. `name` is the key it had in a dict of rooms.
sim::WallMarker marker_from_python(py::handle obj, const std::string& where, const std::string& name) {
  sim::WallMarker m;
  py::object id = field_of(obj, "id");
  if (id.is_none()) id = field_of(obj, "marker");
  if (id.is_none()) throw SchemaError(where + ".id", "missing (give id or marker: the tag36h11 id)");
  m.id = integer(id, where + ".id");
  const py::object at = field_of(obj, "at");
  if (!at.is_none()) {
    if (!py::isinstance<py::sequence>(at) || py::len(at) != 2) throw SchemaError(where + ".at", "expected (x, y)");
    const auto s = py::reinterpret_borrow<py::sequence>(at);
    m.x = finite_number(s[0], where + ".at");
    m.y = finite_number(s[1], where + ".at");
  } else {
    const py::object x = field_of(obj, "x"), y = field_of(obj, "y");
    if (x.is_none() || y.is_none()) throw SchemaError(where + ".at", "missing (give at=(x, y) or x and y)");
    m.x = finite_number(x, where + ".x");
    m.y = finite_number(y, where + ".y");
  }
  const py::object facing = field_of(obj, "facing");
  if (facing.is_none()) throw SchemaError(where + ".facing", "missing (the direction the marker faces, radians)");
  m.facing = finite_number(facing, where + ".facing");
  if (const py::object v = field_of(obj, "size"); !v.is_none()) m.size = finite_number(v, where + ".size");
  if (const py::object v = field_of(obj, "height"); !v.is_none()) m.height = finite_number(v, where + ".height");
  py::object label = field_of(obj, "label");
  if (label.is_none()) label = field_of(obj, "name");
  m.label = label.is_none() ? name : py::str(label).cast<std::string>();
  return m;
}

/// Markers from a list (or any iterable) of markers, or a dict of name -> marker (RobotWorld.rooms).
std::vector<sim::WallMarker> markers_from_python(py::handle obj) {
  std::vector<sim::WallMarker> out;
  if (obj.is_none()) return out;
  if (py::isinstance<py::dict>(obj)) {
    for (auto [key, value] : py::reinterpret_borrow<py::dict>(obj)) {
      const std::string name = py::str(key).cast<std::string>();
      out.push_back(marker_from_python(value, "markers[" + name + "]", name));
    }
    return out;
  }
  if (!py::isinstance<py::iterable>(obj) || py::isinstance<py::str>(obj)) {
    throw SchemaError("markers", "expected a list of markers (dicts or objects with id, at, facing, ...) or a dict of rooms");
  }
  std::size_t i = 0;
  for (py::handle item : obj) {
    out.push_back(marker_from_python(item, "markers[" + std::to_string(i) + "]", ""));
    ++i;
  }
  return out;
}

/// A robot from a dict or an object: pose (x, y, yaw) (vwg.RobotState), or start
/// (vwg.robotworld.RobotSpec), or x, y, theta; optional radius and id.
sim::RobotShape robot_from_python(py::handle obj, const std::string& where) {
  sim::RobotShape r;
  py::object pose = field_of(obj, "pose");
  if (pose.is_none()) pose = field_of(obj, "start");
  if (!pose.is_none()) {
    r.pose = pose_from_python(pose, where + ".pose");
  } else {
    const py::object x = field_of(obj, "x"), y = field_of(obj, "y"), theta = field_of(obj, "theta");
    if (x.is_none() || y.is_none()) throw SchemaError(where + ".pose", "missing (give pose=(x, y, yaw) or x and y)");
    r.pose = {finite_number(x, where + ".x"), finite_number(y, where + ".y"), theta.is_none() ? 0.0 : finite_number(theta, where + ".theta")};
  }
  if (const py::object v = field_of(obj, "radius"); !v.is_none()) r.radius = finite_number(v, where + ".radius");
  if (const py::object v = field_of(obj, "id"); !v.is_none()) r.id = integer(v, where + ".id");
  return r;
}

std::vector<sim::RobotShape> robots_from_python(py::handle obj) {
  std::vector<sim::RobotShape> out;
  if (obj.is_none()) return out;
  if (!py::isinstance<py::iterable>(obj) || py::isinstance<py::str>(obj) || py::isinstance<py::dict>(obj)) {
    throw SchemaError("robots", "expected a list of robots (vwg.RobotState, RobotSpec, or dicts with pose and radius)");
  }
  std::size_t i = 0;
  for (py::handle item : obj) {
    out.push_back(robot_from_python(item, "robots[" + std::to_string(i) + "]"));
    ++i;
  }
  return out;
}

/// A renderer and the lock its renders take turns on.
struct Camera {
  Camera(sim::OccupancyGrid grid, std::vector<sim::WallMarker> markers, sim::CameraSpec spec, int threshold, std::uint64_t seed)
      : renderer(grid, std::move(markers), spec, threshold, seed) {}
  sim::CameraRenderer renderer;
  std::mutex mutex;
};

sim::OverviewView view_from(int width, int height, double azimuth, double elevation, double fov, double robot_height,
                            bool labels, int supersample, const py::object& target, const py::object& scale,
                            const py::object& distance) {
  sim::OverviewView v;
  v.width = width;
  v.height = height;
  v.azimuth = azimuth;
  v.elevation = elevation;
  v.fov = fov;
  v.robot_height = robot_height;
  v.labels = labels;
  v.supersample = supersample;
  if (!target.is_none()) {
    v.fit = false;
    if (!py::isinstance<py::sequence>(target) || (py::len(target) != 2 && py::len(target) != 3)) {
      throw SchemaError("target", "expected (x, y) or (x, y, z), metres");
    }
    const auto t = py::reinterpret_borrow<py::sequence>(target);
    v.target_x = finite_number(t[0], "target");
    v.target_y = finite_number(t[1], "target");
    v.target_z = py::len(t) == 3 ? finite_number(t[2], "target") : 0.0;
    if (!scale.is_none()) v.scale = finite_number(scale, "scale");
    if (!distance.is_none()) v.distance = finite_number(distance, "distance");
  } else if (!scale.is_none() || !distance.is_none()) {
    throw SchemaError(scale.is_none() ? "distance" : "scale", "only with a target (without one, the view frames the map)");
  }
  return v;
}

constexpr const char* kViewArgs =
    "azimuth: direction from the map's centre towards the eye, radians counter-clockwise from +x (-π/2: from the "
    "south). elevation: how steeply the eye looks down, radians (π/2: straight down). fov: horizontal field of view, "
    "radians; 0 = orthographic. Without target the view frames the map's free cells and their walls; with target "
    "(x, y[, z]) it aims there with scale pixels per metre (orthographic) or the eye distance metres away "
    "(perspective).";

/// A 3D vector as Python has always seen the overview's axes: a list [x, y, z].
std::array<double, 3> xyz(const sim::Vec3& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

std::vector<sim::WallMarker> wall_markers_from_python(py::handle markers) { return markers_from_python(markers); }

void init_camera(py::module_& m) {
  py::class_<Camera, std::shared_ptr<Camera>>(m, "CameraRenderer", R"doc(
The simulated robot camera: first-person images of the world made from the 2D map, with the
AprilTag (tag36h11) markers of the rooms on their walls.

Walls are the blocked cells (>= threshold) extruded from the floor to wall_height, with a ceiling
there; other robots are cylinders robot_height tall; the camera sits mount_height above the floor,
level, looking along the pose's heading. The projection is an exact pinhole with fx = fy =
(width/2) / tan(hfov/2) and (cx, cy) = ((width-1)/2, (height-1)/2) (OpenCV: pixel centres at whole
numbers). A marker's size is the edge of its outer black square; the square drawn on the wall is
the tag with its white ring, 10/8 × size. noise: standard deviation of added grey levels; blur:
Gaussian sigma in pixels (before the noise); seed: the noise sequence.

markers: a list of dicts or objects (vwg.robotworld.Room) with id (or marker), at=(x, y) (or x and
y), facing, and optionally size (0.3), height (0.6), label; or RobotWorld.rooms (a dict).)doc")
      .def(py::init([](MapArg grid, py::object markers, const sim::CameraSpec& spec, std::uint64_t seed, int threshold) {
             sim::OccupancyGrid g = grid_from_python(grid);
             std::vector<sim::WallMarker> ms = markers_from_python(markers);
             py::gil_scoped_release release;  // the raycaster's tables and the normals take a while on big maps
             return std::make_shared<Camera>(std::move(g), std::move(ms), spec, threshold, seed);
           }),
           py::arg("grid"), py::arg("markers") = py::list(), py::arg("spec") = sim::CameraSpec{}, py::arg("seed") = sim::CameraRenderer::kDefaultSeed,
           py::arg("threshold") = sim::kObstacleThreshold)
      .def(
          "render",
          [](Camera& cam, PoseArg pose, py::object robots, bool grey) {
            const sim::Pose2 p = pose_from_python(pose, "pose");
            const std::vector<sim::RobotShape> others = robots_from_python(robots);
            const sim::CameraSpec& spec = cam.renderer.spec();
            // Render straight into the array's memory (render() keeps a buffer of the right size).
            py::array_t<std::uint8_t> out = grey ? py::array_t<std::uint8_t>({spec.height, spec.width})
                                                 : py::array_t<std::uint8_t>({spec.height, spec.width, 3});
            cv::Mat view(spec.height, spec.width, grey ? CV_8UC1 : CV_8UC3, out.mutable_data());
            {
              py::gil_scoped_release release;
              std::lock_guard<std::mutex> lock(cam.mutex);
              cam.renderer.render(p, others, view, grey ? sim::PixelFormat::Grey : sim::PixelFormat::Rgb);
            }
            return out;
          },
          py::arg("pose"), py::arg("robots") = py::list(), py::arg("grey") = false,
          "The image seen from pose (x, y, yaw): H×W×3 uint8 RGB, or H×W uint8 grey (the luma) with grey=True. "
          "robots: the other robots (vwg.RobotState, RobotSpec, or dicts with pose and radius, optional id for the "
          "colour); a robot whose cylinder holds the camera is skipped. Releases the GIL.")
      .def(
          "reseed", [](Camera& cam, std::uint64_t seed) {
            std::lock_guard<std::mutex> lock(cam.mutex);
            cam.renderer.reseed(seed);
          },
          py::arg("seed"), "Restart the noise sequence.")
      .def(
          "apriltag_intrinsics",
          [](const Camera& cam) {
            const perception::CameraIntrinsics k = cam.renderer.apriltag_intrinsics();
            return py::make_tuple(k.fx, k.fy, k.cx, k.cy);
          },
          "(fx, fy, cx, cy) for vwg.estimate_tag_pose on these images: the detector puts pixel centres at +0.5, so "
          "cx, cy are this camera's + 0.5.")
      .def_property_readonly("fx", [](const Camera& c) { return c.renderer.spec().fx(); }, "Focal length, pixels.")
      .def_property_readonly("fy", [](const Camera& c) { return c.renderer.spec().fy(); }, "Focal length, pixels (= fx).")
      .def_property_readonly("cx", [](const Camera& c) { return c.renderer.spec().cx(); }, "Principal point, OpenCV convention: (width - 1) / 2.")
      .def_property_readonly("cy", [](const Camera& c) { return c.renderer.spec().cy(); }, "Principal point, OpenCV convention: (height - 1) / 2.")
      .def_property_readonly("width", [](const Camera& c) { return c.renderer.spec().width; })
      .def_property_readonly("height", [](const Camera& c) { return c.renderer.spec().height; })
      .def_property_readonly("hfov", [](const Camera& c) { return c.renderer.spec().hfov; }, "Horizontal field of view, radians.")
      .def_property_readonly("mount_height", [](const Camera& c) { return c.renderer.spec().mount_height; })
      .def_property_readonly("wall_height", [](const Camera& c) { return c.renderer.spec().wall_height; })
      .def_property_readonly("robot_height", [](const Camera& c) { return c.renderer.spec().robot_height; })
      .def_property_readonly("noise", [](const Camera& c) { return c.renderer.spec().noise; })
      .def_property_readonly("blur", [](const Camera& c) { return c.renderer.spec().blur; })
      .def_property_readonly(
          "markers",
          [](const Camera& c) {
            py::list out;
            for (const sim::WallMarker& mk : c.renderer.markers()) {
              out.append(py::dict(py::arg("id") = mk.id, py::arg("at") = py::make_tuple(mk.x, mk.y), py::arg("facing") = mk.facing,
                                  py::arg("size") = mk.size, py::arg("height") = mk.height, py::arg("label") = mk.label));
            }
            return out;
          },
          "The markers as read: dicts with id, at, facing, size, height, label.")
      .def("__repr__", [](const Camera& c) {
        const sim::CameraSpec& s = c.renderer.spec();
        return "vwg.CameraRenderer(" + std::to_string(s.width) + "×" + std::to_string(s.height) + ", " +
               std::to_string(c.renderer.markers().size()) + " markers)";
      });

  py::class_<sim::OverviewCamera>(m, "OverviewCamera", "The projection of a 3D overview: world points (metres, z up) to pixels.")
      .def_readonly("width", &sim::OverviewCamera::width)
      .def_readonly("height", &sim::OverviewCamera::height)
      .def_readonly("orthographic", &sim::OverviewCamera::orthographic)
      .def_property_readonly("eye", [](const sim::OverviewCamera& c) { return xyz(c.eye); },
                             "The eye (orthographic: a point far behind the scene).")
      .def_property_readonly("right", [](const sim::OverviewCamera& c) { return xyz(c.right); },
                             "The image's x axis in the world.")
      .def_property_readonly("down", [](const sim::OverviewCamera& c) { return xyz(c.down); },
                             "The image's y axis in the world.")
      .def_property_readonly("forward", [](const sim::OverviewCamera& c) { return xyz(c.forward); }, "The line of sight.")
      .def_readonly("focal", &sim::OverviewCamera::focal, "Perspective: pixels per unit x/z; orthographic: pixels per metre.")
      .def_readonly("cu", &sim::OverviewCamera::cu)
      .def_readonly("cv", &sim::OverviewCamera::cv)
      .def(
          "project",
          [](const sim::OverviewCamera& c, double x, double y, double z) -> py::object {
            double u, v;
            if (!c.project(x, y, z, u, v)) return py::none();
            return py::make_tuple(u, v);
          },
          py::arg("x"), py::arg("y"), py::arg("z") = 0.0,
          "Pixel (u, v) of a world point (OpenCV convention: pixel centres at whole numbers); None behind the eye.");

  m.def(
      "overview_camera",
      [](MapArg grid, double wall_height, int width, int height, double azimuth, double elevation, double fov,
         int threshold, py::object target, py::object scale, py::object distance) {
        const sim::OccupancyGrid g = grid_from_python(grid);
        const sim::OverviewView v = view_from(width, height, azimuth, elevation, fov, sim::OverviewView{}.robot_height, false, 1, target,
                                              scale, distance);
        return sim::overview_camera(g, wall_height, v, threshold);
      },
      py::arg("grid"), py::arg("wall_height") = sim::kDefaultWallHeight, py::arg("width") = sim::OverviewView{}.width,
      py::arg("height") = sim::OverviewView{}.height, py::arg("azimuth") = sim::OverviewView{}.azimuth,
      py::arg("elevation") = sim::OverviewView{}.elevation, py::arg("fov") = sim::OverviewView{}.fov,
      py::arg("threshold") = sim::kObstacleThreshold, py::arg("target") = py::none(),
      py::arg("scale") = py::none(), py::arg("distance") = py::none(),
      (std::string("The projection render_overview uses with these arguments (to draw over its image). ") + kViewArgs).c_str());

  m.def(
      "render_overview",
      [](MapArg grid, py::object markers, py::object robots, double wall_height, int width, int height, double azimuth,
         double elevation, double fov, double robot_height, bool labels, int supersample, int threshold, py::object target,
         py::object scale, py::object distance) {
        const sim::OccupancyGrid g = grid_from_python(grid);
        const std::vector<sim::WallMarker> ms = markers_from_python(markers);
        const std::vector<sim::RobotShape> rs = robots_from_python(robots);
        const sim::OverviewView v =
            view_from(width, height, azimuth, elevation, fov, robot_height, labels, supersample, target, scale, distance);
        cv::Mat image;
        {
          py::gil_scoped_release release;
          image = sim::render_overview(g, wall_height, ms, rs, v, threshold);
        }
        return rgb_to_numpy(image);
      },
      py::arg("grid"), py::arg("markers") = py::list(), py::arg("robots") = py::list(), py::arg("wall_height") = sim::kDefaultWallHeight,
      py::arg("width") = sim::OverviewView{}.width, py::arg("height") = sim::OverviewView{}.height,
      py::arg("azimuth") = sim::OverviewView{}.azimuth, py::arg("elevation") = sim::OverviewView{}.elevation,
      py::arg("fov") = sim::OverviewView{}.fov, py::arg("robot_height") = sim::OverviewView{}.robot_height,
      py::arg("labels") = sim::OverviewView{}.labels, py::arg("supersample") = sim::OverviewView{}.supersample,
      py::arg("threshold") = sim::kObstacleThreshold,
      py::arg("target") = py::none(), py::arg("scale") = py::none(), py::arg("distance") = py::none(),
      (std::string("A 3D overview of a map (the paper's Fig. 5) as an H×W×3 uint8 RGB array: walls (cells >= "
                   "threshold) extruded to wall_height and lit, the floor with their shadows and 1 m tiles, the markers "
                   "(as for CameraRenderer) as their tags in an orange frame with their labels, robots (as for "
                   "CameraRenderer.render) as cylinders in the 2D view's colours. ") +
       kViewArgs + " supersample: rays per pixel side (1..4). Releases the GIL.")
          .c_str());
}

}  // namespace vwg::bindings
