// vwg's log sink in Python: set_log_sink(fn) makes fn(level, source, message) receive what vwg and
// the libraries it wraps (OMPL) say; vwg/logs.py forwards it to the `logging` module.
#include <memory>
#include <string>

#include "common.hpp"
#include "vwg/log.hpp"

namespace vwg::bindings {

void init_log(py::module_& m) {
  m.def(
      "set_log_sink",
      [](py::object fn) {
        if (fn.is_none()) {
          set_log_sink({});
          return;
        }
        // The last owner of the Python callable may be a planner thread that holds no GIL.
        std::shared_ptr<py::object> callable(new py::object(std::move(fn)), [](py::object* o) {
          py::gil_scoped_acquire gil;
          delete o;
        });
        set_log_sink([callable](LogLevel level, std::string_view source, std::string_view message) {
          if (!Py_IsInitialized()) return;
          py::gil_scoped_acquire gil;
          try {
            (*callable)(static_cast<int>(level), std::string(source), std::string(message));
          } catch (py::error_already_set& e) {
            e.discard_as_unraisable("vwg log sink");  // a failing logger must not fail a plan
          }
        });
      },
      py::arg("sink"),
      "Send vwg's and its libraries' messages to sink(level, source, message) (levels as in `logging`); "
      "None drops them. Used by vwg.logs; called from any thread.");
}

}  // namespace vwg::bindings
