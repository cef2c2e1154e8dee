// vwg's log sink in Python: set_log_sink(fn) makes fn(level, source, message) receive what vwg and
// the libraries it wraps (OMPL) say; vwg/logs.py forwards it to the `logging` module.
#include <cmath>
#include <memory>
#include <string>

#include "common.hpp"
#include "python_budget.hpp"
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
  m.def(
      "set_python_budget",
      [](double seconds) {
        if (!std::isfinite(seconds) || seconds < 0 || seconds > 86400) {
          throw SchemaError("python_budget", "expected 0 (no reports) to 86400 seconds, got " + format_real(seconds));
        }
        set_python_budget(seconds);
      },
      py::arg("seconds"),
      "The time one call of a Python part (an actor's λ or θ, a generator, a backend, a decider) may take "
      "before a warning names it and its time (logger `vwg`); 0 turns the reports off; default 1 s. Only "
      "reported: the frames never depend on a clock.");
  m.def("python_budget", &python_budget, "The time budget of one call of a Python part, seconds (0: off).");
  m.def(
      "log_message",
      [](int level, const std::string& source, const std::string& message) {
        if (level != 10 && level != 20 && level != 30 && level != 40) {
          throw SchemaError("level", "expected 10, 20, 30 or 40 (logging's DEBUG, INFO, WARNING, ERROR), got " +
                                         std::to_string(level));
        }
        log(static_cast<LogLevel>(level), source, message);
      },
      py::arg("level"), py::arg("source"), py::arg("message"),
      "Say `message` through vwg's log sink, as its C++ parts do (a C++ extension's messages, a test of the route).");
}

}  // namespace vwg::bindings
