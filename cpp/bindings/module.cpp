// vwg._core: the compiled part of the vwg Python package (re-exported by vwg/__init__.py).
#include "common.hpp"

PYBIND11_MODULE(_core, m) {
  m.doc() = "The C++ core of vwg, the Virtual Worlds Generator (use it through `import vwg`).";
  m.attr("__version__") = VWG_VERSION_INFO;
  using namespace vwg::bindings;
  init_errors(m);
  init_values(m);
  init_alphabet(m);
  init_strings(m);
  init_events(m);
  init_actors(m);
  init_generators(m);
  init_backends(m);
  init_engine(m);
  init_bench_actors(m);
}
