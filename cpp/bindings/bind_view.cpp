// SimView: the simulation drawn from above as a backend, to PNG files and a FrameSink (the video
// writer of vwg.video, in Python).
#include <memory>
#include <optional>
#include <string>

#include "sim_convert.hpp"
#include "vwg/sim/frame_sink.hpp"
#include "vwg/sim/sim_view.hpp"

namespace vwg::bindings {

namespace {

/// A FrameSink written in Python: each frame goes to its write() as an H×W×3 uint8 copy (the
/// caller's image lives only during the call), taking the GIL.
class PyFrameSink final : public sim::FrameSink {
 public:
  void write(const cv::Mat& rgb) override {
    py::gil_scoped_acquire gil;
    py::function fn = py::get_override(static_cast<const sim::FrameSink*>(this), "write");
    if (!fn) throw Error("a vwg.FrameSink subclass must define write(self, image)");
    fn(rgb_to_numpy(rgb));
  }
  void close() override { PYBIND11_OVERRIDE_PURE(void, sim::FrameSink, close, ); }
};

/// The sink a Python object implements, keeping that object alive as long as C++ holds it (its
/// methods are Python); the reference is dropped under the GIL, whichever thread lets go last.
std::shared_ptr<sim::FrameSink> sink_from_python(const py::object& sink) {
  if (!py::isinstance<sim::FrameSink>(sink)) {
    throw SchemaError("sink", "expected a vwg.FrameSink (a vwg.VideoWriter, for one), got " + python_type_name(sink));
  }
  auto* raw = sink.cast<sim::FrameSink*>();
  return std::shared_ptr<sim::FrameSink>(raw, [keep = sink](sim::FrameSink*) mutable {
    py::gil_scoped_acquire gil;
    keep = py::object();
  });
}

}  // namespace

void init_view(py::module_& m) {
  py::class_<sim::FrameSink, PyFrameSink, std::shared_ptr<sim::FrameSink>>(m, "FrameSink", R"doc(
Where a SimView hands its rendered frames (the C++ interface FrameSink). Subclass it in Python and
define ``write(self, image)`` (an H×W×3 uint8 RGB array, the sink's own copy) and ``close(self)``
(called once at the end, only after frames were written); call ``super().__init__()``.
vwg.VideoWriter is one.)doc")
      .def(py::init<>())
      .def("close", &sim::FrameSink::close, "Finish the recording.");
  py::class_<sim::SimView, Backend, std::shared_ptr<sim::SimView>>(m, "SimView", R"doc(
The simulation drawn from above, as a backend (paper Table I: α(Robot) draws the robot): each
frame, the map, room markers, the robots displayed this frame at their true poses with their
trajectories, the scans of the lasers and Kinects added, and the paths and beliefs set. Put it
after the SimBackend in a BackendGroup. Frames go to a video (a FrameSink: vwg.VideoWriter writes MP4 H.264
or GIF) and/or PNG files; without either nothing is drawn.)doc")
      .def(py::init([](std::shared_ptr<platform::RobotPlatform> platform, MapArg grid, std::optional<sim::RenderStyle> style,
                       int width, int header) {
             sim::RenderStyle s = style ? *style : sim::RenderStyle{};
             if (!style) {
               s.width = width;
               s.header = header;
             }
             return std::make_shared<sim::SimView>(std::move(platform), grid_from_python(grid), s);
           }),
           py::arg("platform"), py::arg("grid"), py::arg("style") = py::none(),
           py::arg("width") = sim::SimView::kDefaultWidth, py::arg("header") = sim::SimView::kDefaultHeader)
      .def("add_laser", &sim::SimView::add_laser, py::arg("laser"))
      .def("add_kinect", &sim::SimView::add_kinect, py::arg("kinect"))
      .def("add_marker", &sim::SimView::add_marker, py::arg("x"), py::arg("y"), py::arg("facing"), py::arg("label"),
           py::arg("tag_id"))
      .def("set_belief", [](sim::SimView& v, int robot, py::object cells) {
             if (cells.is_none()) return v.set_belief(robot, {});
             py::array_t<std::int8_t, py::array::c_style | py::array::forcecast> a(cells);
             v.set_belief(robot, std::vector<std::int8_t>(a.data(), a.data() + a.size()));
           }, py::arg("robot"), py::arg("cells"), "The robot's own grid (int8, the map's shape); None removes it.")
      .def("record_video", [](sim::SimView& v, const py::object& sink) { v.record_video(sink_from_python(sink)); },
           py::arg("sink"),
           "Hand every frame to `sink` (a vwg.FrameSink, such as vwg.VideoWriter(path, fps=...)); its close() "
           "is called by close() or finish().")
      .def("record_images", &sim::SimView::record_images, py::arg("directory"), "Write every frame as frame_00001.png, ...")
      .def("close", py::overload_cast<>(&sim::SimView::close), py::call_guard<py::gil_scoped_release>(),
           "Finish the video (the sink's close(), if it was given frames); later frames are not recorded.")
      .def("finish", [](sim::SimView& v, int hold_frames, std::optional<WorldString> final_view) {
             py::gil_scoped_release release;
             v.finish(hold_frames, final_view ? &*final_view : nullptr);
           }, py::arg("hold_frames") = sim::SimView::kDefaultHoldFrames, py::arg("final") = py::none(),
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
