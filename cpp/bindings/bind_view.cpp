// SimView: the simulation drawn from above as a backend, to PNG files and MP4/GIF videos.
#include <optional>
#include <string>

#include "sim_convert.hpp"
#include "vwg/sim/sim_view.hpp"

namespace vwg::bindings {

void init_view(py::module_& m) {
  py::class_<sim::SimView, Backend, std::shared_ptr<sim::SimView>>(m, "SimView", R"doc(
The simulation drawn from above, as a backend (paper Table I: α(Robot) draws the robot): each
frame, the map, room markers, the robots displayed this frame at their true poses with their
trajectories, the scans of the lasers and Kinects added, and the paths and beliefs set. Put it
after the SimBackend in a BackendGroup. Frames go to a video (MP4 H.264 or GIF) and/or PNG files.)doc")
      .def(py::init([](std::shared_ptr<sim::PhysicsWorld> world, std::optional<sim::RenderStyle> style, int width, int header) {
             sim::RenderStyle s = style ? *style : sim::RenderStyle{};
             if (!style) {
               s.width = width;
               s.header = header;
             }
             return std::make_shared<sim::SimView>(std::move(world), s);
           }),
           py::arg("world"), py::arg("style") = py::none(), py::arg("width") = 800, py::arg("header") = 40)
      .def("add_laser", &sim::SimView::add_laser, py::arg("laser"))
      .def("add_kinect", &sim::SimView::add_kinect, py::arg("kinect"))
      .def("add_marker", &sim::SimView::add_marker, py::arg("x"), py::arg("y"), py::arg("facing"), py::arg("label"),
           py::arg("tag_id"))
      .def("set_belief", [](sim::SimView& v, int robot, py::object cells) {
             if (cells.is_none()) return v.set_belief(robot, {});
             py::array_t<std::int8_t, py::array::c_style | py::array::forcecast> a(cells);
             v.set_belief(robot, std::vector<std::int8_t>(a.data(), a.data() + a.size()));
           }, py::arg("robot"), py::arg("cells"), "The robot's own grid (int8, the map's shape); None removes it.")
      .def("record_video", [](sim::SimView& v, const std::string& path, double fps) { v.record_video(path, fps); },
           py::arg("path"), py::arg("fps") = 10.0, "Write every frame to an MP4 (H.264) or GIF video.")
      .def("record_images", &sim::SimView::record_images, py::arg("directory"), "Write every frame as frame_00001.png, ...")
      .def("close", py::overload_cast<>(&sim::SimView::close), py::call_guard<py::gil_scoped_release>(),
           "Finish the video.")
      .def("finish", [](sim::SimView& v, int hold_frames, std::optional<WorldString> final_view) {
             py::gil_scoped_release release;
             v.finish(hold_frames, final_view ? &*final_view : nullptr);
           }, py::arg("hold_frames") = 10, py::arg("final") = py::none(),
           "Draw the last frame again — with `final`, the displayable string of the state reached (π of the last "
           "string), shown instead of the last frame's — write it hold_frames times to the video (once to the "
           "images), and close.")
      .def("image", [](sim::SimView& v) { return rgb_to_numpy(v.image()); }, "The last frame (H×W×3 uint8, a copy).")
      .def_property_readonly("frames_written", &sim::SimView::frames_written)
      .def_property_readonly("trajectories", [](const sim::SimView& v) {
        py::dict out;
        for (const auto& [id, points] : v.trajectories()) {
          py::array_t<double> a({static_cast<py::ssize_t>(points.size()), py::ssize_t{2}});
          for (std::size_t i = 0; i < points.size(); ++i) {
            a.mutable_at(i, 0) = points[i].x;
            a.mutable_at(i, 1) = points[i].y;
          }
          out[py::int_(id)] = a;
        }
        return out;
      }, "Each robot's true positions, one per frame (N×2).");
}

}  // namespace vwg::bindings
