// vwg._core: the compiled part of the vwg Python package (re-exported by vwg/__init__.py).
#include "common.hpp"

PYBIND11_MODULE(_core, m) {
  m.doc() = "The C++ core of vwg, the Virtual Worlds Generator (use it through `import vwg`).";
  m.attr("__version__") = VWG_VERSION_INFO;
  using namespace vwg::bindings;
  init_errors(m);
  init_log(m);
  init_values(m);
  // Classes whose methods refer to each other are declared first, so every signature names
  // Python types (the methods are added by the init functions below).
  py::class_<vwg::Alphabet, std::shared_ptr<vwg::Alphabet>>(m, "Alphabet");
  py::class_<vwg::WorldString>(m, "String");
  py::class_<vwg::ActorBehavior, std::shared_ptr<vwg::ActorBehavior>>(m, "ActorBehavior",
                                                                      "λ and θ of an actor type (C++, or PythonActor).");
  init_events(m);
  init_backends(m);
  init_generators(m);
  init_actors(m);
  init_strings(m);
  init_alphabet(m);
  init_settings(m);
  init_platform(m);  // before the engine, whose keep_robots_in_step takes a RobotPlatform
  init_engine(m);
  init_bench_actors(m);
  init_sim(m);
  init_physics(m);
  init_render(m);
  init_perception(m);
  init_sensors(m);
  init_view(m);
  init_geometry(m);
  init_plan(m);
  init_robot(m);
  init_camera(m);
  init_camera_generator(m);
  init_registries(m);
  init_localization(m);
  init_avoidance(m);
  init_people(m);
}
