// Shared declarations of the pybind11 module vwg._core (private to cpp/bindings/).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <span>
#include <string>

#include "vwg/vwg.hpp"

namespace vwg::bindings {

namespace py = pybind11;

// --- module parts (one per file, as OMPL's py-bindings do) ---
void init_errors(py::module_& m);
void init_values(py::module_& m);
void init_alphabet(py::module_& m);
void init_strings(py::module_& m);
void init_events(py::module_& m);
void init_actors(py::module_& m);
void init_generators(py::module_& m);
void init_backends(py::module_& m);
void init_engine(py::module_& m);
void init_bench_actors(py::module_& m);
void init_sim(py::module_& m);
void init_settings(py::module_& m);
void init_platform(py::module_& m);
void init_physics(py::module_& m);
void init_render(py::module_& m);
void init_perception(py::module_& m);
void init_sensors(py::module_& m);
void init_view(py::module_& m);
void init_geometry(py::module_& m);
void init_plan(py::module_& m);
void init_robot(py::module_& m);
void init_camera(py::module_& m);
void init_camera_generator(py::module_& m);
void init_log(py::module_& m);
void init_registries(py::module_& m);
void init_localization(py::module_& m);
void init_avoidance(py::module_& m);
void init_people(py::module_& m);

/// A class declared earlier in the module, to add methods to it.
template <class... Options>
py::class_<Options...> declared_class(py::module_& m, const char* name, const char* doc) {
  auto cls = py::reinterpret_borrow<py::class_<Options...>>(m.attr(name));
  if (doc) cls.attr("__doc__") = doc;
  return cls;
}

// --- saved runs (vwg/state.hpp) ---
/// The state of a generator or decider written in Python: its save_state() if its class defines
/// one (bytes), else its attributes as vwg.model.state.capture() writes them (refused, naming the
/// attribute, when one is of a kind it cannot keep). `what` names it in errors ("generator food_drops").
void save_python_state(py::handle self, StateWriter& out, const std::string& what);
/// Back: its load_state(data) if its class defines one, else vwg.model.state.restore().
void load_python_state(py::handle self, StateReader& in, const std::string& what);

/// save_state() of a part (a generator, decider or platform) as Python bytes; the GIL is released
/// while it runs (a Python part's own methods take it again).
template <class Part>
py::bytes saved_state(const Part& part) {
  StateWriter out;
  {
    py::gil_scoped_release release;
    part.save_state(out);
  }
  return py::bytes(out.bytes());
}

/// load_state() of a part from Python bytes, errors naming `what`; `seconds`: the saved run's time,
/// which nothing the state holds may exceed (StateReader::limit_seconds).
template <class Part>
void load_saved_state(Part& part, const py::bytes& data, const std::string& what,
                      std::optional<double> seconds = std::nullopt) {
  const std::string bytes = data;
  StateReader in(bytes, what);
  if (seconds) in.limit_seconds(*seconds);
  py::gil_scoped_release release;
  part.load_state(in);
}

// --- values ---
/// A Python value as a Datum of the kind `spec` declares (or inferred when `spec` is null).
/// Raises vwg::SchemaError naming `field` when it does not fit.
Datum datum_from_python(py::handle obj, const ParamSpec* spec, const std::string& field);
py::object value_to_python(const ValueStore& store, const Value& v);
py::object datum_to_python(const Datum& d);
/// A Blob from a vwg.Blob or a numpy array (copied).
std::shared_ptr<const Blob> blob_from_python(py::handle obj, const std::string& field);
py::object blob_to_python(const std::shared_ptr<const Blob>& blob);
/// A schema from Python: None (any positional values, if allowed), a dict of name -> default
/// value or type (int, float, bool, str, vwg.Blob), or a list of names (reals, required).
Schema schema_from_python(py::handle spec, const std::string& owner, bool allow_variadic);
/// Python description of a schema: {name: (kind, default or None)}.
py::dict schema_to_python(const Schema& schema);

// --- strings ---
/// Append what a λ or θ returned: text, a vwg.String, an actor instance, a vwg.Sym, or a list or
/// tuple of these (concatenated). Raises with `what` (e.g. "Blinker.on_tick") in the message.
void append_python(StringBuilder& out, py::handle obj, const std::string& what);
/// A Python vwg.Node for one node of a string.
py::object node_to_python(const NodeView& node);

// --- events ---
/// Calls f(blob) for the blob of each blob-valued slot of `w`, in the string's order (a blob held
/// twice, twice).
template <class F>
void for_each_blob(const WorldString& w, F&& f) {
  for (const Node& n : w.nodes()) {
    if (n.kind == NodeKind::Close) continue;
    for (std::uint16_t k = 0; k < n.value_count; ++k) {
      const Value& v = w.store()[n.first_value + k];
      if (v.kind == ValueKind::Blob) f(w.store().blob(v));
    }
  }
}
/// A Python vwg.Event for one event.
py::object event_to_python(const EventView& e);
/// The events at positions `at` of `events` (a run of one type) as a vwg.EventColumns.
py::object event_run_to_python(const EventList& events, std::span<const std::uint32_t> at);
/// The events in order, each run of at least `min_run` consecutive events of one type whose fields
/// are all numbers or bools (all with a target or none) as (type, n, targets or None, [(field, kind,
/// column)]) with kind "f", "i" or "b" and columns float64, int64 or bool; every other event as
/// its text. A recorder stores such a run by columns.
py::list event_runs_to_python(const EventList& events, std::size_t min_run);
/// Append a Python vwg.Event (or its text) to `out`.
void emit_python(EventList& out, py::handle obj, const std::string& what);
EventList events_from_python(const std::shared_ptr<const Alphabet>& alphabet, py::handle events);

// --- frames ---
/// The Python view of a FrameInfo, valid only while the call it is passed to runs.
struct PyFrame {
  std::uint64_t frame = 0;
  double time = 0.0;
  double dt = 0.0;
  const WorldString* world = nullptr;
};
py::object frame_to_python(const FrameInfo& info, std::shared_ptr<PyFrame>& holder);

/// The `name` a Python subclass sets as a class attribute (a str), else the class's __name__.
std::string python_type_name(py::handle self);

/// Cached Python objects of the pure-Python part of the package (vwg.actor.Actor, vwg.actor.Sym,
/// vwg.errors.*), imported on first use.
py::object python_class(const char* module, const char* name);

}  // namespace vwg::bindings

// --- arguments checked by the callee, typed for the stubs ---
namespace vwg::bindings {

inline bool accept_any(PyObject*) { return true; }

/// An argument taken as any Python object and checked by the function, so that a bad one raises a
/// vwg error naming it rather than pybind11's TypeError; `Tag::name` only gives signatures and
/// stubs the type the argument should have (a map is any object with .data, .resolution and
/// .origin, typed as the C++ grid vwg._core.OccupancyGrid, which vwg.io.maps.OccupancyGrid is).
template <class Tag>
class LooseArg : public py::object {
 public:
  PYBIND11_OBJECT_DEFAULT(LooseArg, py::object, accept_any)
};

struct MapTag {
  static constexpr auto name = py::detail::const_name("OccupancyGrid");
};
struct PoseTag {
  static constexpr auto name = py::detail::const_name("tuple[float, float, float]");
};
struct IntTag {
  static constexpr auto name = py::detail::const_name("int");
};
struct RealTag {
  static constexpr auto name = py::detail::const_name("float");
};
using MapArg = LooseArg<MapTag>;
using PoseArg = LooseArg<PoseTag>;
using IntArg = LooseArg<IntTag>;
using RealArg = LooseArg<RealTag>;

}  // namespace vwg::bindings

namespace pybind11::detail {
template <class Tag>
struct handle_type_name<vwg::bindings::LooseArg<Tag>> {
  static constexpr auto name = Tag::name;
};
}  // namespace pybind11::detail
