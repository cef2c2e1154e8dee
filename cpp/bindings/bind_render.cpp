// The renderers of vwg._core: TopDownRenderer (2D frames of the simulation), RenderStyle and
// ImageSequence (numbered PNG files). Videos are written by vwg.video (PyAV).
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "common.hpp"
#include "sim_convert.hpp"
#include "vwg/sim/image_io.hpp"
#include "vwg/sim/render2d.hpp"

namespace vwg::bindings {

namespace {

using Colour = std::tuple<int, int, int>;
using PoseTuple = std::tuple<double, double, double>;

sim::Rgb rgb_from(const Colour& c, const std::string& field) {
  const auto [r, g, b] = c;
  for (int v : {r, g, b}) {
    if (v < 0 || v > 255) throw SchemaError(field, "colour channels must be 0..255, got (" + std::to_string(r) + ", " +
                                                       std::to_string(g) + ", " + std::to_string(b) + ")");
  }
  return {static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(g), static_cast<std::uint8_t>(b)};
}

Colour rgb_to(sim::Rgb c) { return {c.r, c.g, c.b}; }

sim::Pose2 pose_from(const PoseTuple& p) { return {std::get<0>(p), std::get<1>(p), std::get<2>(p)}; }

/// An int8 grid (rows × columns, row 0 = bottom) from a numpy array or an object with a `data`
/// array (vwg.OccupancyGrid). Values are copied.
py::array_t<std::int8_t> cells_of(py::handle obj, const std::string& field) {
  py::handle source = obj;
  py::object data;
  if (!py::isinstance<py::array>(obj) && py::hasattr(obj, "data")) {
    data = obj.attr("data");
    source = data;
  }
  if (!py::isinstance<py::array>(source)) {
    throw SchemaError(field, "expected an int8 numpy array (rows × columns, row 0 = bottom) or a vwg.OccupancyGrid");
  }
  auto a = py::reinterpret_borrow<py::array>(source);
  if (!a.dtype().is(py::dtype::of<std::int8_t>())) {
    throw SchemaError(field, "expected an int8 array (-1 unknown, 0 free .. 100 occupied), got " +
                                 std::string(py::str(a.dtype())));
  }
  if (a.ndim() != 2 || a.shape(0) == 0 || a.shape(1) == 0) {
    throw SchemaError(field, "expected a non-empty 2-D array (rows × columns), got " + std::to_string(a.ndim()) +
                                 " dimension(s)");
  }
  return py::array_t<std::int8_t, py::array::c_style>::ensure(a);
}

std::span<const std::int8_t> span_of(const py::array_t<std::int8_t>& a) {
  return {a.data(), static_cast<std::size_t>(a.size())};
}

/// The cells of a grid for a renderer: same shape as its map.
py::array_t<std::int8_t> cells_for(const sim::TopDownRenderer& r, py::handle obj, const std::string& field) {
  auto a = cells_of(obj, field);
  if (a.shape(0) != r.grid().height || a.shape(1) != r.grid().width) {
    throw SchemaError(field, "shape (" + std::to_string(a.shape(0)) + ", " + std::to_string(a.shape(1)) +
                                 ") differs from the map's (" + std::to_string(r.grid().height) + ", " +
                                 std::to_string(r.grid().width) + ")");
  }
  return a;
}

std::vector<float> floats_of(py::handle obj, const std::string& field) {
  auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a) {
    PyErr_Clear();
    throw SchemaError(field, "expected a 1-D array of numbers");
  }
  if (a.ndim() > 1) throw SchemaError(field, "expected a 1-D array, got " + std::to_string(a.ndim()) + " dimensions");
  return {a.data(), a.data() + a.size()};
}

/// World points from an N×2 array (or a list of (x, y) pairs).
std::vector<cv::Point2d> points_of(py::handle obj, const std::string& field) {
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a) {
    PyErr_Clear();
    throw SchemaError(field, "expected an N×2 array of (x, y) points in metres");
  }
  if (a.size() == 0) return {};
  if (a.ndim() != 2 || a.shape(1) != 2) throw SchemaError(field, "expected an N×2 array of (x, y) points in metres");
  std::vector<cv::Point2d> pts(static_cast<std::size_t>(a.shape(0)));
  const double* d = a.data();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!std::isfinite(d[2 * i]) || !std::isfinite(d[2 * i + 1])) {
      throw SchemaError(field, "expected finite points; point " + std::to_string(i) + " is (" + format_real(d[2 * i]) +
                                   ", " + format_real(d[2 * i + 1]) + ")");
    }
    pts[i] = {d[2 * i], d[2 * i + 1]};
  }
  return pts;
}

py::array_t<std::uint8_t> image_to_numpy(const cv::Mat& m) {
  py::array_t<std::uint8_t> out({static_cast<py::ssize_t>(m.rows), static_cast<py::ssize_t>(m.cols),
                                 static_cast<py::ssize_t>(m.channels())});
  const std::size_t row = static_cast<std::size_t>(m.cols) * m.elemSize();
  auto* dst = out.mutable_data();
  for (int r = 0; r < m.rows; ++r) std::memcpy(dst + r * row, m.ptr(r), row);
  return out;
}

/// An H×W×3 uint8 frame viewed (not copied) as a cv::Mat; `keep` holds the contiguous array.
cv::Mat frame_of(const py::array& image, py::array& keep, const std::string& what) {
  if (!image.dtype().is(py::dtype::of<std::uint8_t>())) {
    throw SchemaError(what, "expected a uint8 image, got " + std::string(py::str(image.dtype())));
  }
  if (image.ndim() != 3 || image.shape(2) != 3) {
    throw SchemaError(what, "expected an H×W×3 (RGB) image, got " + std::string(py::str(py::tuple(image.attr("shape")))));
  }
  keep = py::array::ensure(image, py::array::c_style);
  return cv::Mat(static_cast<int>(keep.shape(0)), static_cast<int>(keep.shape(1)), CV_8UC3,
                 const_cast<void*>(keep.data()));
}

sim::OccupancyGrid grid_from(py::handle grid, std::optional<double> resolution, std::optional<PoseTuple> origin) {
  const bool is_object = !py::isinstance<py::array>(grid) && py::hasattr(grid, "data");
  if (!resolution) {
    if (!is_object) throw SchemaError("resolution", "give the metres per cell (or pass a vwg.OccupancyGrid)");
    resolution = grid.attr("resolution").cast<double>();
  }
  if (!origin && is_object && py::hasattr(grid, "origin")) origin = grid.attr("origin").cast<PoseTuple>();
  auto cells = cells_of(grid, "grid");
  sim::OccupancyGrid g;
  g.height = static_cast<int>(cells.shape(0));
  g.width = static_cast<int>(cells.shape(1));
  g.resolution = *resolution;
  if (origin) g.origin = pose_from(*origin);
  const auto s = span_of(cells);
  g.data.assign(s.begin(), s.end());
  return g;
}

/// A colour field of RenderStyle as a Python property of (r, g, b) tuples.
template <sim::Rgb sim::RenderStyle::*Field>
void colour_property(py::class_<sim::RenderStyle>& cls, const char* name, const char* doc) {
  cls.def_property(
      name, [](const sim::RenderStyle& s) { return rgb_to(s.*Field); },
      [name](sim::RenderStyle& s, const Colour& c) { s.*Field = rgb_from(c, std::string("RenderStyle.") + name); }, doc);
}

/// The Python ImageSequence, and a lock because writes run without the GIL.
struct PyImageSequence {
  explicit PyImageSequence(sim::ImageSequence s) : seq(std::move(s)) {}
  sim::ImageSequence seq;
  std::mutex mutex;
};

}  // namespace

std::vector<cv::Point2d> points_from_python(py::handle obj, const std::string& field) { return points_of(obj, field); }
py::array_t<std::uint8_t> rgb_to_numpy(const cv::Mat& image) { return image_to_numpy(image); }

void init_render(py::module_& m) {
  // ---------------------------------------------------------------- RenderStyle
  py::class_<sim::RenderStyle> style(m, "RenderStyle",
                                     "Size, colours (RGB tuples) and line widths of a TopDownRenderer.");
  style.def(py::init<>())
      .def_readwrite("pixels_per_cell", &sim::RenderStyle::pixels_per_cell, "Scale; ignored when width > 0.")
      .def_readwrite("width", &sim::RenderStyle::width, "> 0: total image width in pixels (sets the scale).")
      .def_readwrite("margin", &sim::RenderStyle::margin, "Pixels of background around the map.")
      .def_readwrite("header", &sim::RenderStyle::header, "Extra pixels above the map for the corner text.")
      .def_readwrite("even_size", &sim::RenderStyle::even_size, "Round the image up to even sides (for H.264).")
      .def_readwrite("antialias", &sim::RenderStyle::antialias, "Smooth lines, discs and text.")
      .def_readwrite("min_robot_px", &sim::RenderStyle::min_robot_px, "Smallest robot radius drawn, in pixels.")
      .def_readwrite("draw_misses", &sim::RenderStyle::draw_misses, "Draw max-range rays (faint).")
      .def_readwrite("hit_px", &sim::RenderStyle::hit_px, "Radius of a laser hit point, in pixels.")
      .def_readwrite("path_px", &sim::RenderStyle::path_px, "Thickness of planned paths, in pixels.")
      .def_readwrite("trajectory_px", &sim::RenderStyle::trajectory_px, "Thickness of trajectories, in pixels.")
      .def_readwrite("trajectory_fade", &sim::RenderStyle::trajectory_fade, "Newest points over which a trail fades in.")
      .def_readwrite("trajectory_faint", &sim::RenderStyle::trajectory_faint, "Strength (0..1) of a trail's old part.")
      .def_readwrite("marker_px", &sim::RenderStyle::marker_px, "Thickness of wall markers, in pixels.")
      .def_readwrite("marker_length", &sim::RenderStyle::marker_length, "Length of wall markers, in metres.")
      .def_readwrite("belief_occupied_alpha", &sim::RenderStyle::belief_occupied_alpha, "Opacity of believed walls.")
      .def_readwrite("belief_free_alpha", &sim::RenderStyle::belief_free_alpha, "Opacity of believed free space.")
      .def_readwrite("text_box_alpha", &sim::RenderStyle::text_box_alpha, "Opacity of the box under the corner text.")
      .def_readwrite("font_scale", &sim::RenderStyle::font_scale, "Size of the text (OpenCV Hershey scale).");
  colour_property<&sim::RenderStyle::background>(style, "background", "Around the map.");
  colour_property<&sim::RenderStyle::free>(style, "free", "Free cells.");
  colour_property<&sim::RenderStyle::occupied>(style, "occupied", "Occupied cells.");
  colour_property<&sim::RenderStyle::unknown>(style, "unknown", "Unknown cells.");
  colour_property<&sim::RenderStyle::robot_outline>(style, "robot_outline", "Outline of robot discs.");
  colour_property<&sim::RenderStyle::heading>(style, "heading", "Heading line of robots.");
  colour_property<&sim::RenderStyle::person>(style, "person", "People who walk (sand).");
  colour_property<&sim::RenderStyle::ray>(style, "ray", "Laser rays that hit.");
  colour_property<&sim::RenderStyle::ray_miss>(style, "ray_miss", "Laser rays at max range.");
  colour_property<&sim::RenderStyle::hit>(style, "hit", "Laser hit points.");
  colour_property<&sim::RenderStyle::path>(style, "path", "Paths drawn without a robot id.");
  colour_property<&sim::RenderStyle::trajectory>(style, "trajectory", "Trajectories drawn without a robot id.");
  colour_property<&sim::RenderStyle::marker>(style, "marker", "Wall markers.");
  colour_property<&sim::RenderStyle::belief_occupied>(style, "belief_occupied", "Believed walls.");
  colour_property<&sim::RenderStyle::belief_free>(style, "belief_free", "Believed free space.");
  colour_property<&sim::RenderStyle::text>(style, "text", "Corner text.");
  colour_property<&sim::RenderStyle::text_box>(style, "text_box", "Box under the corner text.");
  colour_property<&sim::RenderStyle::label>(style, "label", "Robot and marker labels.");
  style.def_property(
      "palette",
      [](const sim::RenderStyle& s) {
        std::vector<Colour> out;
        for (const sim::Rgb& c : s.palette) out.push_back(rgb_to(c));
        return out;
      },
      [](sim::RenderStyle& s, const std::vector<Colour>& colours) {
        std::vector<sim::Rgb> p;
        for (const Colour& c : colours) p.push_back(rgb_from(c, "RenderStyle.palette"));
        s.palette = std::move(p);
      },
      "Robot colours: robot id i takes palette[i % len(palette)].");

  // ---------------------------------------------------------------- TopDownRenderer
  py::class_<sim::TopDownRenderer>(m, "TopDownRenderer",
                                   "Frames of the 2D simulation seen from above: the map (row 0 at the bottom), "
                                   "robots, laser rays, markers, paths, trajectories, the robot's belief and a "
                                   "corner text. Coordinates are world metres; images are H×W×3 uint8 RGB.")
      .def(py::init([](py::object grid, std::optional<double> resolution, std::optional<PoseTuple> origin,
                       std::optional<double> pixels_per_cell, std::optional<int> width, std::optional<int> margin,
                       std::optional<int> header, std::optional<sim::RenderStyle> style) {
             sim::RenderStyle s = style.value_or(sim::RenderStyle{});
             if (pixels_per_cell) {
               s.pixels_per_cell = *pixels_per_cell;
               s.width = 0;
             }
             if (width) s.width = *width;
             if (margin) s.margin = *margin;
             if (header) s.header = *header;
             return sim::TopDownRenderer(grid_from(grid, resolution, origin), std::move(s));
           }),
           py::arg("grid"), py::arg("resolution") = py::none(), py::arg("origin") = py::none(), py::kw_only(),
           py::arg("pixels_per_cell") = py::none(), py::arg("width") = py::none(), py::arg("margin") = py::none(),
           py::arg("header") = py::none(), py::arg("style") = py::none(),
           "grid: int8 array (rows × columns, row 0 = bottom; -1 unknown, 0 free, 100 occupied) with its "
           "resolution (m per cell) and origin (x, y, yaw) of cell (0, 0)'s lower-left corner, or a "
           "vwg.OccupancyGrid. Scale: pixels_per_cell (default 4) or width (total pixels); other settings "
           "in style.")
      .def("update_map",
           [](sim::TopDownRenderer& r, py::object grid) { r.update_map(span_of(cells_for(r, grid, "grid"))); },
           py::arg("grid"), "Replace the map's cells (same shape) and redraw the cached map layer.")
      .def(
          "begin",
          [](sim::TopDownRenderer& r, std::optional<std::int64_t> frame, std::optional<double> time,
             const std::string& status) {
            sim::FrameText t;
            if (frame) t.frame = *frame;
            if (time) t.time = *time;
            t.status = status;
            r.begin(t);
          },
          py::arg("frame") = py::none(), py::arg("time") = py::none(), py::arg("status") = "",
          "Start a frame: the map, and a corner text 'frame N   t = T s' with a status line (parts left "
          "out when None / empty).")
      .def(
          "draw_robot",
          [](sim::TopDownRenderer& r, const PoseTuple& pose, double radius, int id, std::optional<std::string> label,
             std::optional<Colour> colour) {
            std::optional<sim::Rgb> c;
            if (colour) c = rgb_from(*colour, "colour");
            std::optional<std::string_view> l;
            if (label) l = *label;
            r.draw_robot(pose_from(pose), radius, id, l, c);
          },
          py::arg("pose"), py::arg("radius"), py::arg("id") = sim::TopDownRenderer::kDefaultRobotId, py::arg("label") = py::none(),
          py::arg("colour") = py::none(),
          "A disc of radius metres at pose (x, y, theta) with a heading line, in robot id's palette colour "
          "(or colour), labelled with the id (or label; '' for none).")
      .def(
          "draw_scan",
          [](sim::TopDownRenderer& r, const PoseTuple& pose, py::handle angles, py::handle ranges, double max_range) {
            const auto a = floats_of(angles, "angles");
            const auto d = floats_of(ranges, "ranges");
            r.draw_scan(pose_from(pose), a, d, max_range);
          },
          py::arg("pose"), py::arg("angles"), py::arg("ranges"),
          py::arg("max_range") = std::numeric_limits<double>::infinity(),
          "Laser rays from the sensor pose (x, y, theta): angles (radians, relative to theta) and ranges "
          "(metres), 1-D arrays of one length. Ranges that are inf/NaN or reach max_range are misses, drawn faint.")
      .def("draw_marker", &sim::TopDownRenderer::draw_marker, py::arg("x"), py::arg("y"), py::arg("facing"),
           py::arg("label") = "", py::arg("tag_id") = sim::TopDownRenderer::kNoId,
           "A wall marker at (x, y) facing the direction `facing` (radians): a thick segment along the wall, "
           "labelled 'label #tag_id' on the side it faces.")
      .def(
          "draw_path",
          [](sim::TopDownRenderer& r, py::handle points, int id) { r.draw_path(points_of(points, "points"), id); },
          py::arg("points"), py::arg("id") = sim::TopDownRenderer::kNoId,
          "A planned path: N×2 world points (metres), ending in a ring at the goal; robot id's colour if id >= 0.")
      .def(
          "draw_trajectory",
          [](sim::TopDownRenderer& r, py::handle points, int id) {
            r.draw_trajectory(points_of(points, "points"), id);
          },
          py::arg("points"), py::arg("id") = sim::TopDownRenderer::kNoId, "A trajectory: N×2 world points, oldest first, fading into the past.")
      .def("draw_start", &sim::TopDownRenderer::draw_start, py::arg("x"), py::arg("y"), py::arg("id"),
           "Where robot id started: a hollow square in its colour.")
      .def(
          "draw_legend",
          [](sim::TopDownRenderer& r, const std::vector<std::pair<int, std::string>>& entries) {
            std::vector<sim::TopDownRenderer::LegendEntry> out;
            for (const auto& [id, text] : entries) out.push_back({id, text});
            r.draw_legend(std::move(out));
          },
          py::arg("entries"),
          "A legend in the top-right corner: (robot id, text) per line, with the key of the start and final marks.")
      .def(
          "draw_belief",
          [](sim::TopDownRenderer& r, py::object grid) { r.draw_belief(span_of(cells_for(r, grid, "grid"))); },
          py::arg("grid"),
          "The robot's map: an int8 grid of the map's shape blended over it (unknown cells leave the map visible).")
      .def(
          "image", [](sim::TopDownRenderer& r) { return image_to_numpy(r.image()); },
          "The frame as an H×W×3 uint8 RGB array (a copy).")
      .def(
          "save",
          [](sim::TopDownRenderer& r, const std::filesystem::path& path) {
            const cv::Mat frame = r.image().clone();  // the copy can be encoded without the GIL
            py::gil_scoped_release release;
            sim::write_image(path.string(), frame);
          },
          py::arg("path"), "Write the frame to an image file (PNG; the format follows the extension).")
      .def(
          "world_to_pixel",
          [](const sim::TopDownRenderer& r, double x, double y) {
            const cv::Point2d p = r.world_to_pixel(x, y);
            return std::make_tuple(p.x, p.y);
          },
          py::arg("x"), py::arg("y"),
          "Continuous pixel coordinates (column, row) of a world point: pixel (i, j) covers [i, i+1) × [j, j+1), "
          "so image[int(row), int(col)] is the pixel under the point.")
      .def(
          "pixel_to_world",
          [](const sim::TopDownRenderer& r, double px, double py) {
            const sim::Pose2 p = r.pixel_to_world(px, py);
            return std::make_tuple(p.x, p.y);
          },
          py::arg("px"), py::arg("py"), "The world point (x, y) at continuous pixel coordinates.")
      .def("robot_colour", [](const sim::TopDownRenderer& r, int id) { return rgb_to(r.robot_colour(id)); },
           py::arg("id"), "The (r, g, b) colour robot id is drawn in.")
      .def_property_readonly("width", [](const sim::TopDownRenderer& r) { return r.size().width; }, "Image width.")
      .def_property_readonly("height", [](const sim::TopDownRenderer& r) { return r.size().height; }, "Image height.")
      .def_property_readonly("pixels_per_cell", &sim::TopDownRenderer::pixels_per_cell, "Scale.")
      .def_property_readonly("pixels_per_metre", &sim::TopDownRenderer::pixels_per_metre, "Scale.")
      .def_property_readonly(
          "map_rect",
          [](const sim::TopDownRenderer& r) {
            const cv::Rect q = r.map_rect();
            return std::make_tuple(q.x, q.y, q.width, q.height);
          },
          "Where the map lies in the image: (x, y, width, height) in pixels.")
      .def_property_readonly(
          "style", [](const sim::TopDownRenderer& r) { return r.style(); },
          "The settings (a copy: changing it does not change the renderer).");

  // ---------------------------------------------------------------- ImageSequence
  py::class_<PyImageSequence>(m, "ImageSequence",
                              "Frames as numbered PNG files in a folder: frame_00001.png, frame_00002.png, ...")
      .def(py::init([](const std::filesystem::path& directory, const std::string& prefix, int first, int digits) {
             return std::make_unique<PyImageSequence>(sim::ImageSequence(directory.string(), prefix, first, digits));
           }),
           py::arg("directory"), py::arg("prefix") = sim::ImageSequence::kDefaultPrefix,
           py::arg("first") = sim::ImageSequence::kDefaultFirst, py::arg("digits") = sim::ImageSequence::kDefaultDigits,
           "Creates the folder if needed; frame files are prefix + the number with `digits` digits + '.png'.")
      .def(
          "write",
          [](PyImageSequence& s, const py::array& image) {
            py::array keep;
            const cv::Mat frame = frame_of(image, keep, "image");
            py::gil_scoped_release release;
            std::lock_guard<std::mutex> lock(s.mutex);
            return s.seq.write(frame);
          },
          py::arg("image"), "Write the next H×W×3 uint8 RGB frame; returns the file's path.")
      .def(
          "path_of", [](const PyImageSequence& s, std::int64_t number) { return s.seq.path_of(number); },
          py::arg("number"), "The path of frame `number`.")
      .def_property_readonly("directory", [](const PyImageSequence& s) { return s.seq.directory(); })
      .def_property_readonly(
          "frames",
          [](PyImageSequence& s) {
            std::lock_guard<std::mutex> lock(s.mutex);
            return s.seq.frames();
          },
          "Frames written.");
}

}  // namespace vwg::bindings
