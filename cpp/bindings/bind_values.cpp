// vwg.Blob: a large attribute value (a grid, an image), seen from Python as a read-only numpy array
// without a copy; the array keeps the blob alive.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

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

namespace {

std::string shape_text(std::span<const std::int64_t> shape) {
  std::string out;
  for (auto e : shape) out += (out.empty() ? "(" : ", ") + std::to_string(e);
  return out.empty() ? "()" : out + ")";
}

/// The elements of two blobs of `count` elements of type U whose bits differ: their indices and the
/// new bits XOR the old. None when there are more than `most`.
template <class U>
py::object changes_of(const std::byte* p, const std::byte* q, std::size_t count, std::size_t most) {
  std::vector<std::int64_t> where;
  std::vector<U> values;
  auto load = [](const std::byte* at) {
    U x;
    std::memcpy(&x, at, sizeof x);
    return x;
  };
  auto look = [&](std::size_t first, std::size_t last) {  // elements [first, last)
    for (std::size_t e = first; e < last; ++e) {
      const U x = static_cast<U>(load(p + e * sizeof(U)) ^ load(q + e * sizeof(U)));
      if (x == 0) continue;
      if (where.size() == most) return false;
      where.push_back(static_cast<std::int64_t>(e));
      values.push_back(x);
    }
    return true;
  };
  // Equal stretches are skipped 256 bytes at a time: one OR of XORs of 8-byte words, which the
  // compiler turns into vector instructions (about 8 times faster than a memcmp a stretch).
  constexpr std::size_t kStretch = 256;
  constexpr std::size_t kPer = kStretch / sizeof(U);
  const std::size_t whole = count / kPer;
  for (std::size_t s = 0; s < whole; ++s) {
    const std::byte* ps = p + s * kStretch;
    const std::byte* qs = q + s * kStretch;
    std::uint64_t differs = 0;
    for (std::size_t w = 0; w < kStretch / 8; ++w) {
      std::uint64_t x;
      std::uint64_t y;
      std::memcpy(&x, ps + w * 8, 8);
      std::memcpy(&y, qs + w * 8, 8);
      differs |= x ^ y;
    }
    if (differs != 0 && !look(s * kPer, (s + 1) * kPer)) return py::none();
  }
  if (!look(whole * kPer, count)) return py::none();
  return py::make_tuple(py::array_t<std::int64_t>(static_cast<py::ssize_t>(where.size()), where.data()),
                        py::array_t<U>(static_cast<py::ssize_t>(values.size()), values.data()));
}

/// Blob.changes_from: the elements of `b` whose bits differ from `base`'s.
py::object blob_changes(const Blob& b, const Blob& base, std::optional<std::int64_t> limit) {
  if (b.dtype() != base.dtype() || !std::ranges::equal(b.shape(), base.shape())) {
    throw SchemaError("base", "expected a blob of the same dtype and shape as " + std::string(dtype_name(b.dtype())) + " " +
                                  shape_text(b.shape()) + ", got " + std::string(dtype_name(base.dtype())) + " " + shape_text(base.shape()));
  }
  if (limit && *limit < 0) throw SchemaError("limit", "expected a count of elements >= 0, got " + std::to_string(*limit));
  const std::size_t size = dtype_size(b.dtype());
  const std::size_t count = b.nbytes() / size;
  const std::size_t most = limit ? static_cast<std::size_t>(*limit) : count;
  switch (size) {
    case 1: return changes_of<std::uint8_t>(b.data(), base.data(), count, most);
    case 2: return changes_of<std::uint16_t>(b.data(), base.data(), count, most);
    case 4: return changes_of<std::uint32_t>(b.data(), base.data(), count, most);
    default: return changes_of<std::uint64_t>(b.data(), base.data(), count, most);
  }
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
      .def("changes_from", &blob_changes, py::arg("base"), py::arg("limit") = py::none(), R"doc(
Where this blob differs from ``base`` (same dtype and shape), element by element as bits:
``(positions, values)``, the flat C-order indices of the elements that differ (int64, ascending)
and those elements XOR the base's, as unsigned ints of the element's size. None when more than
``limit`` elements differ (it stops counting there). Equal stretches are skipped 256 bytes at a
time, so a grid with a few changed cells costs about a pass over memory.)doc")
      .def("__repr__", [](const Blob& b) {
        return "vwg.Blob(" + std::string(dtype_name(b.dtype())) + ", " + shape_text(b.shape()) + ", @" + blob_name(b).substr(1) + ")";
      });
}

}  // namespace vwg::bindings
