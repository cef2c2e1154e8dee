// The simulation side of vwg._core: image files, occupancy grids, and (as they land) the physics
// world, sensors and renderers.
#include <cstring>
#include <string>

#include "common.hpp"
#include "vwg/sim/image_io.hpp"

namespace vwg::bindings {

namespace {

py::array mat_to_numpy(const cv::Mat& m) {
  std::vector<py::ssize_t> shape{m.rows, m.cols};
  if (m.channels() > 1) shape.push_back(m.channels());
  py::array out = m.depth() == CV_16U ? py::array(py::dtype::of<std::uint16_t>(), shape)
                                      : py::array(py::dtype::of<std::uint8_t>(), shape);
  const std::size_t row_bytes = static_cast<std::size_t>(m.cols) * m.elemSize();
  auto* dst = static_cast<std::uint8_t*>(out.mutable_data());
  for (int r = 0; r < m.rows; ++r) std::memcpy(dst + r * row_bytes, m.ptr(r), row_bytes);
  return out;
}

cv::Mat numpy_to_mat(const py::array& a, const std::string& what) {
  if (a.ndim() != 2 && !(a.ndim() == 3 && (a.shape(2) == 1 || a.shape(2) == 3 || a.shape(2) == 4))) {
    throw SchemaError(what, "expected an H×W, H×W×3 or H×W×4 array");
  }
  const int channels = a.ndim() == 3 ? static_cast<int>(a.shape(2)) : 1;
  int type;
  if (a.dtype().is(py::dtype::of<std::uint8_t>())) type = CV_MAKETYPE(CV_8U, channels);
  else if (a.dtype().is(py::dtype::of<std::uint16_t>())) type = CV_MAKETYPE(CV_16U, channels);
  else throw SchemaError(what, "expected a uint8 or uint16 array, got " + std::string(py::str(a.dtype())));
  py::array c = py::array::ensure(a, py::array::c_style);
  cv::Mat m(static_cast<int>(c.shape(0)), static_cast<int>(c.shape(1)), type, const_cast<void*>(c.data()));
  return m.clone();
}

}  // namespace

void init_sim(py::module_& m) {
  m.def("read_image", [](const std::string& path) {
         cv::Mat image = sim::read_image(path);
         return mat_to_numpy(image);
       }, py::arg("path"),
       "Read an image file (PNG, PGM, BMP, JPEG) as stored: uint8 or uint16, H×W, H×W×3 (RGB) or H×W×4 (RGBA).");
  m.def("write_image", [](const std::string& path, py::array image) {
         cv::Mat mat = numpy_to_mat(image, "image");
         py::gil_scoped_release release;
         sim::write_image(path, mat);
       }, py::arg("path"), py::arg("image"), "Write an H×W (grey), H×W×3 (RGB) or H×W×4 (RGBA) uint8/uint16 image.");
}

}  // namespace vwg::bindings
