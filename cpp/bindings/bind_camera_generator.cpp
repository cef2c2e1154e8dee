// gCamera in Python: the generator and its image sources (simulated camera, image files, video
// file, live camera).
#include <array>
#include <functional>
#include <optional>
#include <string>

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include "sim_convert.hpp"
#include "vwg/perception/camera_generator.hpp"
#include "vwg/perception/image_source.hpp"
#include "vwg/sim/camera_source.hpp"

namespace vwg::bindings {

void init_camera_generator(py::module_& m) {
  py::class_<perception::ImageSource, std::shared_ptr<perception::ImageSource>>(m, "ImageSource",
      "Where gCamera's images come from: SimulatedCamera, ImageFiles or VideoSource.");
  py::class_<perception::ImageFiles, perception::ImageSource, std::shared_ptr<perception::ImageFiles>>(m, "ImageFiles",
      "One image file per frame, in order (none after the last).")
      .def(py::init<std::vector<std::string>>(), py::arg("paths"));
  py::class_<perception::VideoSource, perception::ImageSource, std::shared_ptr<perception::VideoSource>>(m, "VideoSource",
      "A video file, or a live camera (a device number), through OpenCV: one image per frame.")
      .def(py::init<const std::string&>(), py::arg("path"))
      .def(py::init<int>(), py::arg("device"));
  py::class_<perception::ReceivedImages, perception::ImageSource, std::shared_ptr<perception::ReceivedImages>>(
      m, "ReceivedImages",
      "The latest compressed image (JPEG or PNG bytes) a robot's link received: push() it from any thread "
      "with its stamp (the link's clock); a frame gets it when it is new. Images that do not decode are "
      "dropped and counted. ``viewpoint(stamp)`` gives where the robot was at a stamp, (x ahead, y left, "
      "theta) in its frame at this frame, or None: tags are placed from there, and an image whose stamp it "
      "does not know is counted as stale and not searched.")
      .def(py::init([](std::optional<std::function<std::optional<std::array<double, 3>>(double)>> viewpoint) {
             perception::Viewpoint at;
             if (viewpoint) {
               at = [f = std::move(*viewpoint)](double stamp) -> std::optional<geometry::Pose2> {
                 const auto p = f(stamp);
                 if (!p) return std::nullopt;
                 return geometry::Pose2{(*p)[0], (*p)[1], (*p)[2]};
               };
             }
             return std::make_shared<perception::ReceivedImages>(std::move(at));
           }), py::arg("viewpoint") = py::none())
      .def("push", [](perception::ReceivedImages& r, const py::bytes& encoded, double stamp) {
             const std::string_view view(encoded);
             r.push(std::vector<std::uint8_t>(view.begin(), view.end()), stamp);
           }, py::arg("encoded"), py::arg("stamp"))
      .def_property_readonly("received", &perception::ReceivedImages::received)
      .def_property_readonly("dropped", &perception::ReceivedImages::dropped)
      .def_property_readonly("stale", &perception::ReceivedImages::stale,
                             "Images not searched: taken when the viewpoint knows no pose (None).");
  m.def("encode_image", [](py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast> image,
                           const std::string& format, int quality) {
          const bool grey = image.ndim() == 2, rgb = image.ndim() == 3 && image.shape(2) == 3;
          if (!grey && !rgb) throw SchemaError("image", "expected an H×W grey or H×W×3 RGB uint8 image");
          const cv::Mat view(static_cast<int>(image.shape(0)), static_cast<int>(image.shape(1)), grey ? CV_8UC1 : CV_8UC3,
                             const_cast<std::uint8_t*>(image.data()));
          std::vector<std::uint8_t> out;
          {
            py::gil_scoped_release release;
            out = perception::encode_image(view, format, quality);
          }
          return py::bytes(reinterpret_cast<const char*>(out.data()), out.size());
        }, py::arg("image"), py::arg("format") = "jpeg", py::arg("quality") = perception::kDefaultJpegQuality,
        "JPEG or PNG bytes of an image (as sensor_msgs/CompressedImage carries them).");
  py::class_<sim::SimulatedCamera, perception::ImageSource, std::shared_ptr<sim::SimulatedCamera>>(m, "SimulatedCamera",
      "The robot's view in the simulated world (see CameraRenderer), other robots included.")
      .def(py::init([](std::shared_ptr<sim::PhysicsWorld> world, int robot, MapArg grid, py::object markers,
                       const sim::CameraSpec& spec, std::uint64_t seed) {
             auto renderer = std::make_shared<sim::CameraRenderer>(grid_from_python(grid), wall_markers_from_python(markers),
                                                                  spec, sim::kObstacleThreshold, seed);
             return std::make_shared<sim::SimulatedCamera>(std::move(world), robot, std::move(renderer));
           }),
           py::arg("world"), py::arg("robot"), py::arg("grid"), py::arg("markers"), py::arg("spec") = sim::CameraSpec{},
           py::arg("seed") = sim::CameraRenderer::kDefaultSeed)
      .def("apriltag_intrinsics", [](const sim::SimulatedCamera& c) {
        const auto i = c.renderer().apriltag_intrinsics();
        return py::make_tuple(i.fx, i.fy, i.cx, i.cy);
      }, "(fx, fy, cx, cy) in the AprilTag library's pixel convention, for CameraGenerator.");

  py::class_<perception::CameraGenerator, Generator, std::shared_ptr<perception::CameraGenerator>>(m, "CameraGenerator", R"doc(
gCamera: each frame an image from `source`; for each AprilTag found, eCamera<to=robot, marker, dist,
angle> with the tag id, its horizontal distance (metres) and bearing (radians, left positive),
from the tag pose (intrinsics in the AprilTag convention: pixel centres at +0.5; tag_size: edge of
the black square, or tag_sizes per id). ``image`` is the last image, ``detections`` its tags.)doc")
      .def(py::init([](std::shared_ptr<perception::ImageSource> source, int robot, const Alphabet& alphabet, double fx,
                       double fy, double cx, double cy, double tag_size, std::map<int, double> tag_sizes, double quad_decimate,
                       bool refine_edges, int period, const std::string& event) {
             perception::CameraGeneratorSettings s;
             s.robot = robot;
             s.intrinsics = perception::CameraIntrinsics{fx, fy, cx, cy};
             s.tag_size = tag_size;
             s.tag_sizes = std::move(tag_sizes);
             s.detector.quad_decimate = quad_decimate;
             s.detector.refine_edges = refine_edges;
             s.period = period;
             return std::make_shared<perception::CameraGenerator>(std::move(source), s, alphabet, event);
           }),
           py::arg("source"), py::arg("robot"), py::arg("alphabet"), py::arg("fx"), py::arg("fy"), py::arg("cx"),
           py::arg("cy"), py::arg("tag_size") = perception::CameraGeneratorSettings{}.tag_size,
           py::arg("tag_sizes") = std::map<int, double>{},
           py::arg("quad_decimate") = perception::AprilTagSettings{}.quad_decimate,
           py::arg("refine_edges") = perception::AprilTagSettings{}.refine_edges,
           py::arg("period") = perception::CameraGeneratorSettings{}.period,
           py::arg("event") = "eCamera")
      .def_property_readonly("image", [](const perception::CameraGenerator& g) -> py::object {
        const cv::Mat& im = g.image();
        if (im.empty()) return py::none();
        py::array_t<std::uint8_t> out({im.rows, im.cols});
        for (int r = 0; r < im.rows; ++r) std::memcpy(out.mutable_data(r, 0), im.ptr(r), static_cast<std::size_t>(im.cols));
        return out;
      }, "The last image (grey, a copy), or None.")
      .def_property_readonly("detections", &perception::CameraGenerator::detections, "The tags found in the last image.")
      .def_property_readonly("robot", &perception::CameraGenerator::robot);
}

}  // namespace vwg::bindings
