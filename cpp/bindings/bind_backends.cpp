// Backends (the geometric system G): a base class for backends written in Python, and the C++
// NullBackend and TraceBackend.
#include <string>

#include "common.hpp"
#include "python_budget.hpp"

namespace vwg::bindings {

namespace {

class PyBackend : public Backend {
 public:
  void begin_frame(const FrameInfo& info) override { call_frame("begin_frame", info); }
  void end_frame(const FrameInfo& info) override { call_frame("end_frame", info); }
  void primitive(const NodeView& p) override { call_node("primitive", p); }
  void open(const NodeView& t) override { call_node("open", t); }
  void close(const NodeView& t) override { call_node("close", t); }
  std::string name() const override {
    // The class's `name` if a Python subclass sets one; read on the type, since on the instance a
    // base-class property would call this function again.
    py::gil_scoped_acquire gil;
    return python_type_name(py::cast(this));
  }

 private:
  void call_node(const char* method, const NodeView& node) {
    py::gil_scoped_acquire gil;
    PythonCallTimer timer([&] { return "the Python backend " + name() + "." + method; });
    py::function fn = py::get_override(static_cast<const Backend*>(this), method);
    if (fn) fn(node_to_python(node));
  }
  void call_frame(const char* method, const FrameInfo& info) {
    py::gil_scoped_acquire gil;
    PythonCallTimer timer([&] { return "the Python backend " + name() + "." + method; });
    py::function fn = py::get_override(static_cast<const Backend*>(this), method);
    if (!fn) return;
    std::shared_ptr<PyFrame> holder;
    py::object frame = frame_to_python(info, holder);
    try {
      fn(frame);
    } catch (...) {
      holder->world = nullptr;
      throw;
    }
    holder->world = nullptr;
  }
};

}  // namespace

void init_backends(py::module_& m) {
  py::class_<Backend, PyBackend, std::shared_ptr<Backend>>(m, "Backend", R"doc(
A geometric system G (paper eqs. 1-2). Subclass it in Python and define any of
``primitive(self, p)`` (α), ``open(self, t)`` (β), ``close(self, t)`` (δ) — each gets a vwg.Node —
and ``begin_frame(self, frame)`` / ``end_frame(self, frame)`` (vwg.FrameInfo). Undefined methods do
nothing.)doc")
      .def(py::init<>());
  py::class_<NullBackend, Backend, std::shared_ptr<NullBackend>>(m, "NullBackend", "Does nothing (for timing evolution alone).")
      .def(py::init<>());
  py::class_<TraceBackend, Backend, std::shared_ptr<TraceBackend>>(m, "TraceBackend", R"doc(
Records every call of φ as text: ``'frame 3'`` at each frame start, ``'alpha Robot'``,
``'beta Move<0.5>'``, ``'delta Move<0.5>'``.)doc")
      .def(py::init<>())
      .def_property_readonly("calls", &TraceBackend::calls, "The calls so far, in order.")
      .def("clear", &TraceBackend::clear);
}

}  // namespace vwg::bindings
