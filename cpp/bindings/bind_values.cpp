// vwg.Blob: a large attribute value (a grid, an image), seen from Python as a read-only numpy array
// without a copy; the array keeps the blob alive.
#include <cstdio>
#include <string>

#include "common.hpp"

namespace vwg::bindings {

namespace {
std::string numpy_format(DType d) {
  switch (d) {
    case DType::Int8: return py::format_descriptor<std::int8_t>::format();
    case DType::UInt8: return py::format_descriptor<std::uint8_t>::format();
    case DType::Int16: return py::format_descriptor<std::int16_t>::format();
    case DType::Int32: return py::format_descriptor<std::int32_t>::format();
    case DType::Int64: return py::format_descriptor<std::int64_t>::format();
    case DType::Float32: return py::format_descriptor<float>::format();
    case DType::Float64: return py::format_descriptor<double>::format();
  }
  return "B";
}
}  // namespace

void init_values(py::module_& m) {
  py::class_<Blob, std::shared_ptr<Blob>>(m, "Blob", py::buffer_protocol(), R"doc(
A large attribute value held by reference from world strings (an occupancy grid, an image, a path).

Create one from a numpy array (copied once): ``vwg.Blob(np.zeros((10, 10), np.int8))``.
``numpy.asarray(blob)`` is a read-only view without a copy. In the text form a blob is named by its
content hash, ``@0123456789abcdef``; equal contents have equal names.)doc")
      .def(py::init([](py::handle array) {
             return std::const_pointer_cast<Blob>(blob_from_python(array, "Blob"));
           }),
           py::arg("array"), "Copy a numpy array (int8, uint8, int16, int32, int64, float32 or float64, at most 4-D).")
      .def_buffer([](Blob& b) -> py::buffer_info {
        std::vector<py::ssize_t> shape(b.shape().begin(), b.shape().end());
        std::vector<py::ssize_t> strides(shape.size());
        py::ssize_t stride = static_cast<py::ssize_t>(dtype_size(b.dtype()));
        for (std::size_t k = shape.size(); k-- > 0;) {
          strides[k] = stride;
          stride *= shape[k];
        }
        return py::buffer_info(const_cast<std::byte*>(b.data()), static_cast<py::ssize_t>(dtype_size(b.dtype())),
                               numpy_format(b.dtype()), static_cast<py::ssize_t>(shape.size()), shape, strides,
                               /*readonly=*/true);
      })
      .def_property_readonly("dtype", [](const Blob& b) { return std::string(dtype_name(b.dtype())); }, "numpy dtype name.")
      .def_property_readonly("shape", [](const Blob& b) { return py::tuple(py::cast(std::vector<std::int64_t>(b.shape().begin(), b.shape().end()))); })
      .def_property_readonly("nbytes", &Blob::nbytes)
      .def_property_readonly("name", [](const Blob& b) { return blob_name(b).substr(1); },
                             "The content hash in 16 hex digits: the blob's name in the text form, after '@'.")
      .def("numpy", [](py::object self) { return py::module_::import("numpy").attr("asarray")(self); },
           "A read-only numpy view of the data (no copy).")
      .def("__eq__", [](const Blob& a, py::object other) {
        if (!py::isinstance<Blob>(other)) return false;
        return a.same_content(other.cast<const Blob&>());
      })
      .def("__hash__", [](const Blob& b) { return static_cast<py::ssize_t>(b.content_hash() >> 1); })
      .def("__repr__", [](const Blob& b) {
        std::string shape;
        for (auto e : b.shape()) shape += (shape.empty() ? "" : ", ") + std::to_string(e);
        return "vwg.Blob(" + std::string(dtype_name(b.dtype())) + ", (" + shape + "), @" + blob_name(b).substr(1) + ")";
      });
}

}  // namespace vwg::bindings
