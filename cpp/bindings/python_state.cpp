// What generators and deciders written in Python keep, in a saved run: their own save_state and
// load_state when their class defines them, else their attributes (vwg.model.state).
#include <string>

#include "common.hpp"

namespace vwg::bindings {

namespace {

/// The method `name` of the Python class of `self` when that class (not vwg's base) defines it.
py::object own_method(py::handle self, const char* name) {
  py::object type = py::type::of(self);
  for (py::handle klass : type.attr("__mro__")) {
    if (py::hasattr(klass, "__module__") && py::str(klass.attr("__module__")).cast<std::string>() == "vwg._core") break;
    // A class's __dict__ is a mappingproxy, not a dict: asked through the mapping protocol.
    if (py::bool_(klass.attr("__dict__").attr("__contains__")(name))) return self.attr(name);
  }
  return py::none();
}

}  // namespace

void save_python_state(py::handle self, StateWriter& out, const std::string& what) {
  py::gil_scoped_acquire gil;
  py::object method = own_method(self, "save_state");
  py::object data = method.is_none() ? py::module_::import("vwg.model.state").attr("capture")(self, what) : method();
  if (!py::isinstance<py::bytes>(data)) {
    throw SchemaError(what + ".save_state", "expected bytes, got " + std::string(py::str(py::type::of(data).attr("__name__"))));
  }
  const std::string bytes = data.cast<std::string>();
  out.raw(bytes.data(), bytes.size());
}

void load_python_state(py::handle self, StateReader& in, const std::string& what) {
  std::string bytes(in.left(), '\0');
  in.raw(bytes.data(), bytes.size(), "the state");
  py::gil_scoped_acquire gil;
  py::object method = own_method(self, "load_state");
  if (method.is_none()) {
    py::module_::import("vwg.model.state").attr("restore")(self, py::bytes(bytes), what);
  } else {
    method(py::bytes(bytes));
  }
}

}  // namespace vwg::bindings
