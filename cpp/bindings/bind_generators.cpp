// Event generators C^d(t): the C++ every_frame, and a base class for generators written in Python.
#include <string>

#include "common.hpp"
#include "python_budget.hpp"

namespace vwg::bindings {

namespace {

/// A generator whose generate() is a Python method returning events (vwg.Event, their text, or
/// vwg.EventColumns).
class PyGenerator : public Generator {
 public:
  void generate(const FrameInfo& info, EventList& out) override {
    py::gil_scoped_acquire gil;
    PythonCallTimer timer([this] { return "the Python generator " + name(); });
    py::function fn = py::get_override(static_cast<const Generator*>(this), "generate");
    if (!fn) throw Error("a vwg.Generator subclass must define generate(self, frame)");
    std::shared_ptr<PyFrame> holder;
    py::object frame = frame_to_python(info, holder);
    py::object result;
    try {
      result = fn(frame);
    } catch (...) {
      holder->world = nullptr;
      throw;
    }
    holder->world = nullptr;
    if (result.is_none()) return;  // no events this frame
    std::size_t i = 0;
    const std::string who = name();
    for (auto e : result) emit_python(out, e, who + " event " + std::to_string(i++));
  }
  void reset(std::uint64_t seed) override {
    py::gil_scoped_acquire gil;
    py::function fn = py::get_override(static_cast<const Generator*>(this), "reset");
    if (fn) fn(seed);
  }
  std::string name() const override {
    // The class's `name` if a Python subclass sets one; read on the type, since on the instance a
    // base-class property would call this function again.
    py::gil_scoped_acquire gil;
    return python_type_name(py::cast(this));
  }
  void save_state(StateWriter& out) const override {
    py::gil_scoped_acquire gil;
    save_python_state(py::cast(this), out, "generator " + name());
  }
  void load_state(StateReader& in) override {
    py::gil_scoped_acquire gil;
    load_python_state(py::cast(this), in, "generator " + name());
  }
};

}  // namespace

void init_generators(py::module_& m) {
  py::class_<Generator, PyGenerator, std::shared_ptr<Generator>>(m, "Generator", R"doc(
An event generator C^d(t) (paper eq. 10). Subclass it in Python and define
``generate(self, frame: vwg.FrameInfo)`` returning an iterable of vwg.Event (or event texts, or
vwg.EventColumns for a batch of events given by columns, such as a scan); return None or [] for no
events. Optionally define ``reset(self, seed: int)``: the engine calls it once
with a seed derived from its own seed and the generator's place, so random generators are
reproducible. Generators run in the order given to the engine: their priority.)doc")
      .def(py::init<>())
      .def("generate", [](Generator&, py::object) -> py::object {
        throw Error("generate() is not defined by this generator");
      }, py::arg("frame"))
      .def("reset", [](Generator&, std::uint64_t) {}, py::arg("seed"))
      .def("save_state", &saved_state<Generator>, "What decides its future events, as bytes (a saved run). A Python subclass may define "
         "save_state(self) -> bytes and load_state(self, data); without them its attributes are kept "
         "(numbers, text, lists, dicts, numpy arrays and random generators; others are refused by name).")
      .def("load_state", [](Generator& g, const py::bytes& data) { load_saved_state(g, data, "generator " + g.name()); },
           py::arg("data"), "Back to what save_state() returned.")
      .def_property_readonly("name", &Generator::name, "A short name for messages (a subclass may set `name`).");

  py::class_<EveryFrameGenerator, Generator, std::shared_ptr<EveryFrameGenerator>>(m, "EveryFrame",
      "One event of a fixed type (and fields) every frame: the paper's gDecide and gExecute.")
      .def(py::init([](const Alphabet& alphabet, const std::string& event, std::optional<std::int64_t> target, py::kwargs fields) {
             const EventTypeInfo& info = alphabet.event_type(alphabet.event_type_id(event));
             std::vector<Datum> values;
             for (const auto& spec : info.fields.params) {
               if (fields.contains(spec.name)) {
                 values.push_back(datum_from_python(fields[py::str(spec.name)], &spec, info.name + "." + spec.name));
               } else if (spec.default_value) {
                 values.push_back(*spec.default_value);
               } else {
                 throw SchemaError(info.name + "." + spec.name, "missing (it has no default)");
               }
             }
             for (auto item : fields) {
               if (info.fields.index_of(std::string(py::str(item.first))) < 0) {
                 throw SchemaError(info.name + "." + std::string(py::str(item.first)), "no such field");
               }
             }
             return std::make_shared<EveryFrameGenerator>(alphabet, event, std::move(values), target ? *target : kNoTarget);
           }),
           py::arg("alphabet"), py::arg("event"), py::arg("target") = py::none())
      .def_property_readonly("name", &EveryFrameGenerator::name);
}

}  // namespace vwg::bindings
