// The grid raycaster and the range sensors (gLaser, gKinect) in Python. Scans and depth images
// are copies of the generators' buffers, which change at the next frame.
#include <algorithm>
#include <string>

#include "sim_convert.hpp"
#include "vwg/sim/depth_camera.hpp"
#include "vwg/sim/laser.hpp"
#include "vwg/sim/raycast.hpp"

namespace vwg::bindings {

namespace {

/// A numpy copy of a sensor's buffer: the generator rewrites its buffers every frame, so a view
/// kept by Python would change under it (and outlive a resized buffer).
template <class T>
py::array_t<T> copy_of(const T* data, std::vector<py::ssize_t> shape) {
  py::array_t<T> out(shape);
  std::copy(data, data + out.size(), out.mutable_data());
  return out;
}

py::dict hit_to_python(const sim::RayHit& h) {
  py::dict d;
  d["distance"] = h.distance;
  d["hit"] = h.hit;
  d["row"] = h.row;
  d["col"] = h.col;
  d["face"] = h.face;
  d["point"] = py::make_tuple(h.x, h.y);
  return d;
}

}  // namespace

void init_sensors(py::module_& m) {
  py::class_<sim::GridRaycaster, std::shared_ptr<sim::GridRaycaster>>(m, "GridRaycaster", R"doc(
Exact raycasting over an occupancy grid (cells with a value >= threshold are obstacles): the
simulated laser. ``cast`` gives the hit cell, face and entry point; ``scan`` many ranges at once.)doc")
      .def(py::init([](MapArg grid, int threshold) {
             return std::make_shared<sim::GridRaycaster>(grid_from_python(grid), threshold);
           }), py::arg("grid"), py::arg("threshold") = sim::kObstacleThreshold)
      .def("cast", [](const sim::GridRaycaster& r, double x, double y, double angle, double max_range) {
             return hit_to_python(r.cast(x, y, angle, max_range));
           }, py::arg("x"), py::arg("y"), py::arg("angle"), py::arg("max_range"),
           "The ray from (x, y) along `angle`: {distance, hit, row, col, face, point}.")
      .def("cast_dda", [](const sim::GridRaycaster& r, double x, double y, double angle, double max_range) {
             return hit_to_python(r.cast_dda(x, y, angle, max_range));
           }, py::arg("x"), py::arg("y"), py::arg("angle"), py::arg("max_range"), "The plain cell-walk reference of cast().")
      .def_property_readonly("simd", [](const sim::GridRaycaster& r) { return std::string(r.simd()); },
                             "The code scans run on here: 'avx512', 'avx2' or 'none' (the widest the CPU has, but 'avx2' on AMD's Zen 3 and 4; VWG_RAYCAST_SIMD=avx512, avx2 or none chooses, at most what the CPU has).")
      .def("scan", [](const sim::GridRaycaster& r, PoseArg pose, py::array_t<double, py::array::c_style | py::array::forcecast> angles,
                      double max_range) {
             const sim::Pose2 p = pose_from_python(pose, "pose");
             py::array_t<float> out(angles.size());
             {
               py::gil_scoped_release release;
               r.scan(p, std::span<const double>(angles.data(), static_cast<std::size_t>(angles.size())), max_range,
                      std::span<float>(out.mutable_data(), static_cast<std::size_t>(angles.size())));
             }
             return out;
           }, py::arg("pose"), py::arg("angles"), py::arg("max_range"),
           "Ranges (float32) from pose (x, y, yaw) along yaw + each angle.")
      .def("scans", [](const sim::GridRaycaster& r, py::array_t<double, py::array::c_style | py::array::forcecast> poses,
                       py::array_t<double, py::array::c_style | py::array::forcecast> angles, double max_range,
                       const std::string& method) {
             if (poses.ndim() != 2 || poses.shape(1) != 3) throw SchemaError("poses", "expected an N×3 array of (x, y, yaw)");
             if (method != "fast" && method != "dda") throw SchemaError("method", "expected 'fast' or 'dda'");
             const bool dda = method == "dda";
             const auto n = static_cast<std::size_t>(poses.shape(0)), k = static_cast<std::size_t>(angles.size());
             py::array_t<float> out({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(k)});
             {
               py::gil_scoped_release release;
               for (std::size_t i = 0; i < n; ++i) {
                 const double* p = poses.data() + 3 * i;
                 float* row = out.mutable_data() + i * k;
                 if (dda) {
                   for (std::size_t j = 0; j < k; ++j) row[j] = static_cast<float>(r.cast_dda(p[0], p[1], p[2] + angles.data()[j], max_range).distance);
                 } else {
                   r.scan(sim::Pose2{p[0], p[1], p[2]}, std::span<const double>(angles.data(), k), max_range, std::span<float>(row, k));
                 }
               }
             }
             return out;
           }, py::arg("poses"), py::arg("angles"), py::arg("max_range"), py::arg("method") = "fast",
           "One scan per pose (N×3 array): an N×len(angles) float32 array, by the fast scan or the plain DDA.");

  py::class_<sim::RangeScanner, std::shared_ptr<sim::RangeScanner>>(m, "RangeScanner",
      "Ranges over a map's walls and the other robots of a physics world (shared by the laser and the Kinect).")
      .def(py::init<std::shared_ptr<const sim::GridRaycaster>, std::shared_ptr<const sim::PhysicsWorld>>(),
           py::arg("raycaster"), py::arg("world"))
      .def("scan", [](const sim::RangeScanner& s, int robot, const sim::LaserSpec& spec) {
             const std::vector<double> angles = sim::beam_angles(spec);
             py::array_t<float> out(static_cast<py::ssize_t>(angles.size()));
             const sim::Pose2 pose = s.world().robot(robot).pose;
             {
               py::gil_scoped_release release;
               s.scan(robot, pose, angles, spec.max_range, std::span<float>(out.mutable_data(), angles.size()));
             }
             return out;
           }, py::arg("robot"), py::arg("spec"),
           "Robot `robot`'s noiseless scan from where it is, over spec's beams (beam_angles(spec)): float32 ranges, max_range where nothing was hit.");

  m.def("beam_layout", [](const sim::LaserSpec& spec) {
          sim::check_settings(spec, "laser");
          const sim::BeamLayout l = sim::beam_layout(spec);
          return py::make_tuple(l.angle_min, l.increment);
        }, py::arg("spec"), "The laser's beams as a sensor_msgs/LaserScan lays them out: (angle_min, angle_increment).");
  m.def("beam_angles", [](const sim::LaserSpec& spec) {
          sim::check_settings(spec, "laser");
          const std::vector<double> angles = sim::beam_angles(spec);
          return copy_of(angles.data(), {static_cast<py::ssize_t>(angles.size())});
        }, py::arg("spec"),
        "The laser's beam angles from the heading (radians, float64), as LaserGenerator.angles: angle_min + i·angle_increment.");

  py::class_<sim::LaserGenerator, Generator, std::shared_ptr<sim::LaserGenerator>>(m, "LaserGenerator", R"doc(
gLaser: each frame a scan from the robot's true pose; eLaser<to=robot, dist, angle> for each beam
that hit something. A noisy ``dist`` is a float32 reading, as a real laser's LaserScan carries it.
``ranges`` and ``angles`` are copies of the last scan.)doc")
      .def(py::init<std::shared_ptr<const sim::RangeScanner>, int, sim::LaserSpec, const Alphabet&, const std::string&>(),
           py::arg("scanner"), py::arg("robot"), py::arg("spec"), py::arg("alphabet"), py::arg("event") = "eLaser")
      .def_property_readonly("ranges", [](py::object self) {
        const auto& g = self.cast<const sim::LaserGenerator&>();
        return copy_of(g.ranges().data(), {static_cast<py::ssize_t>(g.ranges().size())});
      }, "The last scan's ranges (float32; max_range where nothing was hit), a copy.")
      .def_property_readonly("angles", [](py::object self) {
        const auto& g = self.cast<const sim::LaserGenerator&>();
        return copy_of(g.angles().data(), {static_cast<py::ssize_t>(g.angles().size())});
      }, "The beam angles from the heading (radians).")
      .def_property_readonly("robot", &sim::LaserGenerator::robot)
      .def_property_readonly("spec", &sim::LaserGenerator::spec)
      .def_property_readonly("max_range", [](const sim::LaserGenerator& g) { return g.spec().max_range; });

  py::class_<sim::KinectGenerator, Generator, std::shared_ptr<sim::KinectGenerator>>(m, "KinectGenerator", R"doc(
gKinect: each frame a depth image from the robot's true pose (walls extruded to wall_height, a
ceiling there, other robots as cylinders), turned into a scan as depthimage_to_laserscan does;
eLaser<to=robot, dist, angle> for each column with a valid range. ``depth`` (H×W float32, metres
along the optical axis, NaN = invalid), ``ranges`` and ``angles`` are copies of the last frame's.)doc")
      .def(py::init<std::shared_ptr<const sim::RangeScanner>, int, sim::DepthCameraSpec, const Alphabet&, const std::string&>(),
           py::arg("scanner"), py::arg("robot"), py::arg("spec"), py::arg("alphabet"), py::arg("event") = "eLaser")
      .def_property_readonly("depth", [](py::object self) {
        const auto& g = self.cast<const sim::KinectGenerator&>();
        const auto& s = g.camera().spec();
        return copy_of(g.depth().data(), {s.height, s.width});
      })
      .def_property_readonly("ranges", [](py::object self) {
        const auto& g = self.cast<const sim::KinectGenerator&>();
        return copy_of(g.ranges().data(), {static_cast<py::ssize_t>(g.ranges().size())});
      })
      .def_property_readonly("angles", [](py::object self) {
        const auto& g = self.cast<const sim::KinectGenerator&>();
        return copy_of(g.angles().data(), {static_cast<py::ssize_t>(g.angles().size())});
      })
      .def_property_readonly("robot", &sim::KinectGenerator::robot)
      .def_property_readonly("spec", [](const sim::KinectGenerator& g) { return g.camera().spec(); });
}

}  // namespace vwg::bindings
