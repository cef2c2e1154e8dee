// vwg._core.Alphabet: the registry of primitives, transformations, actor types and event types.
#include <string>

#include "common.hpp"

namespace vwg::bindings {

namespace {

/// A Python str as bytes for the parser. A lone surrogate (as the surrogateescape error handler leaves
/// for undecodable bytes) is passed through as its three bytes, which the parser's UTF-8 check refuses
/// with its line and column, as it does any byte that is not UTF-8.
std::string text_from_python(const py::str& text) {
  py::object bytes = py::reinterpret_steal<py::object>(PyUnicode_AsEncodedString(text.ptr(), "utf-8", "surrogatepass"));
  if (!bytes) throw py::error_already_set();
  return std::string(py::bytes(bytes));
}

py::list names_of(const Alphabet& a, SymbolKind kind) {
  py::list out;
  for (const auto& s : a.symbols()) {
    if (s.kind == kind) out.append(s.name);
  }
  return out;
}
}  // namespace

void init_alphabet(py::module_& m) {
  declared_class<Alphabet, std::shared_ptr<Alphabet>>(m, "Alphabet", R"doc(
The alphabet of a world (paper §II.A): primitives P, transformations T, actor types A (each with the
event types H it responds to) and event types D with the visual subset V. Append-only; a name is
registered once across all kinds.

Parameters are declared as ``None`` (any positional values), a dict ``{name: default}`` or
``{name: type}`` (a type means required; types are int, float, bool, str and vwg.Blob), or a list
of names (required reals).)doc")
      .def(py::init<>())
      .def("add_primitive", [](Alphabet& a, const std::string& name, py::object params) {
             return a.add_primitive(name, schema_from_python(params, name, true));
           }, py::arg("name"), py::arg("params") = py::none(), "Register a primitive; returns its id.")
      .def("add_transformation", [](Alphabet& a, const std::string& name, py::object params) {
             return a.add_transformation(name, schema_from_python(params, name, true));
           }, py::arg("name"), py::arg("params") = py::none(), "Register a transformation; returns its id.")
      .def("add_event_type", [](Alphabet& a, const std::string& name, bool visual, py::object fields) {
             Schema schema = schema_from_python(fields, name, false);
             if (schema.index_of("target") >= 0) throw SchemaError(name + ".target", "'target' is reserved for the event's target actor");
             return a.add_event_type(name, visual, std::move(schema));
           }, py::arg("name"), py::arg("visual") = false, py::arg("fields") = py::none(),
           "Register an event type (visual ones are seen by θ); returns its id.")
      .def("add_actor", [](Alphabet& a, const std::string& name, const std::vector<std::string>& events,
                           py::object attributes, std::shared_ptr<ActorBehavior> behavior) {
             return a.add_actor(name, events, schema_from_python(attributes, name, false), std::move(behavior));
           }, py::arg("name"), py::arg("events"), py::arg("attributes") = py::none(), py::arg("behavior") = nullptr,
           "Register an actor type responding to `events` (H), with its attributes and behavior (λ, θ).")
      .def("set_behavior", [](Alphabet& a, const std::string& name, std::shared_ptr<ActorBehavior> behavior) {
             a.set_behavior(a.symbol_id(name, SymbolKind::Actor), std::move(behavior));
           }, py::arg("name"), py::arg("behavior"))
      .def("kind_of", [](const Alphabet& a, const std::string& name) -> py::object {
             if (auto id = a.find_symbol(name)) return py::str(std::string(kind_name(a.symbol(*id).kind)));
             if (auto id = a.find_event_type(name)) return py::str(a.event_type(*id).visual ? "visual event" : "event");
             return py::none();
           }, py::arg("name"), "'primitive', 'transformation', 'actor', 'event', 'visual event' or None.")
      .def_property_readonly("primitives", [](const Alphabet& a) { return names_of(a, SymbolKind::Primitive); })
      .def_property_readonly("transformations", [](const Alphabet& a) { return names_of(a, SymbolKind::Transformation); })
      .def_property_readonly("actors", [](const Alphabet& a) { return names_of(a, SymbolKind::Actor); })
      .def_property_readonly("event_types", [](const Alphabet& a) {
        py::list out;
        for (const auto& e : a.event_types()) out.append(e.name);
        return out;
      })
      .def_property_readonly("visual_event_types", [](const Alphabet& a) {
        py::list out;
        for (const auto& e : a.event_types()) {
          if (e.visual) out.append(e.name);
        }
        return out;
      })
      .def("params", [](const Alphabet& a, const std::string& name) -> py::object {
             if (auto id = a.find_symbol(name)) {
               const Schema& s = a.symbol(*id).schema;
               if (s.variadic) return py::none();
               return schema_to_python(s);
             }
             return schema_to_python(a.event_type(a.event_type_id(name)).fields);
           }, py::arg("name"),
           "Declared parameters (attributes, fields) as {name: (kind, default or None)}; None for variadic.")
      .def("responds_to", [](const Alphabet& a, const std::string& name) {
             const SymbolInfo& info = a.symbol(a.symbol_id(name, SymbolKind::Actor));
             py::list out;
             for (auto e : info.responds_to) out.append(a.event_type(e).name);
             return out;
           }, py::arg("actor"), "The event types H an actor type responds to.")
      .def("parse", [](std::shared_ptr<Alphabet> a, const py::str& py_text, std::string_view source, py::object blobs) {
             const std::string text = text_from_python(py_text);
             BlobTable table;
             if (!blobs.is_none()) {
               for (auto item : py::reinterpret_borrow<py::dict>(blobs)) {
                 std::string key = py::str(item.first);
                 if (!key.empty() && key[0] == '@') key.erase(0, 1);
                 table.emplace(key, blob_from_python(item.second, "blobs['" + key + "']"));
               }
             }
             return parse_string(a, text, source, blobs.is_none() ? nullptr : &table);
           }, py::arg("text"), py::arg("source") = "<string>", py::arg("blobs") = py::none(),
           "Parse a world string. `blobs` maps names used after '@' to vwg.Blob or numpy arrays.")
      .def("parse_event", [](std::shared_ptr<Alphabet> a, const py::str& py_text, std::string_view source) {
             const std::string text = text_from_python(py_text);
             EventList list(a);
             parse_event(list, text, source);
             return event_to_python(list[0]);
           }, py::arg("text"), py::arg("source") = "<event>", "Parse one event, e.g. 'eLaser<dist=1.5, angle=0.1>'.")
      .def("empty_string", [](std::shared_ptr<Alphabet> a) { return WorldString(a); }, "The empty string ε.");
}

}  // namespace vwg::bindings
