// C++ errors raised as the Python classes of vwg.errors, with their fields as attributes and, for
// a FrameError, the original exception (a Python one raised inside an actor, say) as __cause__.
#include <string>

#include "common.hpp"

namespace vwg::bindings {

namespace {

/// Text as Python sees it: a message may quote bytes that are not UTF-8 (a damaged state's name, a
/// file's line), which are shown as U+FFFD rather than turning the error into a UnicodeDecodeError.
py::object readable(const std::string& text) {
  return py::reinterpret_steal<py::object>(PyUnicode_DecodeUTF8(text.data(), static_cast<Py_ssize_t>(text.size()), "replace"));
}

py::object make_exception(const char* cls_name, const std::string& message, const py::dict& attrs) {
  py::object cls = python_class("vwg.errors", cls_name);
  py::object exc = cls(readable(message));
  for (auto item : attrs) py::setattr(exc, item.first, item.second);
  return exc;
}

/// The Python exception object for a C++ exception in flight (without raising it).
py::object exception_object(const std::exception_ptr& p) {
  try {
    std::rethrow_exception(p);
  } catch (py::error_already_set& e) {
    return e.value();
  } catch (const FrameError& e) {
    py::dict attrs;
    attrs["frame"] = e.frame();
    attrs["stage"] = readable(e.stage());
    attrs["actor"] = readable(e.actor());
    attrs["event"] = readable(e.event());
    attrs["where"] = readable(e.where());
    std::string message = e.what();
    py::object cause;
    if (e.cause()) {
      cause = exception_object(e.cause());
      // Name a Python cause as "Type: message"; its traceback stays on __cause__.
      if (!cause.is_none() && message.size() >= e.cause_message().size()) {
        const std::string summary = std::string(py::str(py::type::handle_of(cause).attr("__name__"))) + ": " +
                                    std::string(py::str(cause));
        message = message.substr(0, message.size() - e.cause_message().size()) + summary;
      }
    }
    py::object exc = make_exception("FrameError", message, attrs);
    if (cause) {
      PyException_SetCause(exc.ptr(), cause.release().ptr());  // steals the reference
    }
    return exc;
  } catch (const ParseError& e) {
    py::dict attrs;
    attrs["source"] = readable(e.source());
    attrs["line"] = e.line();
    attrs["column"] = e.column();
    attrs["found"] = readable(e.found());
    attrs["expected"] = readable(e.expected());
    return make_exception("ParseError", e.what(), attrs);
  } catch (const FileError& e) {
    // WorldFileError words its message from its parts, as the C++ one does.
    return python_class("vwg.errors", "WorldFileError")(readable(e.path()), readable(e.field()), readable(e.message()),
                                                        e.line(), e.column());
  } catch (const SchemaError& e) {
    py::dict attrs;
    attrs["field"] = readable(e.field());
    return make_exception("SchemaError", e.what(), attrs);
  } catch (const Error& e) {
    return make_exception("Error", e.what(), py::dict());
  } catch (const std::exception& e) {
    return py::reinterpret_borrow<py::object>(PyExc_RuntimeError)(readable(e.what()));
  } catch (...) {
    return py::reinterpret_borrow<py::object>(PyExc_RuntimeError)("unknown C++ exception");
  }
}

}  // namespace

void init_errors(py::module_&) {
  py::register_exception_translator([](std::exception_ptr p) {
    if (!p) return;
    try {
      std::rethrow_exception(p);
    } catch (const FrameError& e) {
      // Ctrl-C (KeyboardInterrupt) or exit() (SystemExit) inside a λ, a generator or a backend is not a
      // failed frame: it goes on as itself (the engine has kept its last complete frame).
      if (e.cause()) {
        py::object cause = exception_object(e.cause());
        if (!cause.is_none() && PyExceptionInstance_Check(cause.ptr()) &&
            !PyObject_IsInstance(cause.ptr(), PyExc_Exception)) {
          PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(cause.ptr())), cause.ptr());
          return;
        }
      }
      py::object exc = exception_object(p);
      PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(exc.ptr())), exc.ptr());
    } catch (const Error&) {
      py::object exc = exception_object(p);
      PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(exc.ptr())), exc.ptr());
    }
    // Anything else falls through to pybind11's own translators.
  });
}

}  // namespace vwg::bindings
