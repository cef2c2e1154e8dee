// vwg.String (a world string, immutable from Python), vwg.Node (one symbol of it), and the
// semantic functions evolve (η), visualize (π) and display (φ).
#include <string>

#include "common.hpp"

namespace vwg::bindings {

namespace {

struct PyNode {
  std::string kind;  // "primitive", "transformation", "actor"
  std::string name;
  std::string text;
  py::tuple params;
  py::dict named;  // by name, when the symbol declares names
  std::size_t index = 0;
  bool joined = false;
};

std::string short_text(const std::string& s) {
  if (s.size() <= 200) return s;
  return s.substr(0, 197) + "...";
}

}  // namespace

py::object node_to_python(const NodeView& node) {
  PyNode n;
  n.kind = std::string(kind_name(node.info().kind));
  n.name = node.info().name;
  n.text = to_text(node);
  n.index = node.index();
  n.joined = node.joined();
  py::tuple params(node.value_count());
  const Schema& schema = node.info().schema;
  for (std::size_t k = 0; k < node.value_count(); ++k) {
    py::object v = value_to_python(node.store(), node.value(k));
    params[k] = v;
    if (!schema.variadic) n.named[py::str(schema.params[k].name)] = v;
  }
  n.params = std::move(params);
  return py::cast(std::move(n));
}

void init_strings(py::module_& m) {
  py::class_<PyNode>(m, "Node", "One symbol of a world string: its kind, name and parameters.")
      .def_readonly("kind", &PyNode::kind, "'primitive', 'transformation' or 'actor'.")
      .def_readonly("name", &PyNode::name)
      .def_readonly("params", &PyNode::params, "Parameter (attribute) values in declaration order.")
      .def_readonly("named", &PyNode::named, "Parameter values by name (empty for symbols declared without names).")
      .def_readonly("index", &PyNode::index, "Position in the string's node array.")
      .def_readonly("text", &PyNode::text, "Canonical text of the symbol alone, e.g. 'Move<0.5>'.")
      .def_readonly("joined", &PyNode::joined,
                    "True for a primitive juxtaposed to the primitive before it, in one figure (rule 6, "
                    "FIGURE → p+): the second node of 'Robot Lamp'.")
      .def("__getitem__", [](const PyNode& n, py::object key) -> py::object {
        if (PyUnicode_Check(key.ptr())) {
          if (!n.named.contains(key)) throw py::key_error(n.name + " has no parameter " + std::string(py::str(key)));
          return n.named[key];
        }
        return n.params[key];
      })
      .def("__repr__", [](const PyNode& n) { return "vwg.Node(" + n.kind + " " + n.text + ")"; })
      .def("__str__", [](const PyNode& n) { return n.text; });

  declared_class<WorldString>(m, "String", R"doc(
A world string w ∈ L(M): primitives, transformations with their scopes, and actors. Immutable;
``str(w)`` is its canonical text, ``len(w)`` its number of symbols; equal strings compare and hash
equal. Build one with ``World.parse`` or as the return value of an actor.)doc")
      .def("__str__", [](const WorldString& w) { return to_text(w); })
      .def("__repr__", [](const WorldString& w) { return "vwg.String(" + short_text(std::string(py::repr(py::str(to_text(w))))) + ")"; })
      .def("__len__", &WorldString::symbol_count)
      .def("__bool__", [](const WorldString& w) { return !w.empty(); })
      .def("__eq__", [](const WorldString& a, py::object other) {
        if (!py::isinstance<WorldString>(other)) return false;
        return a == other.cast<const WorldString&>();
      })
      .def("__hash__", [](const WorldString& w) { return static_cast<py::ssize_t>(w.content_hash() >> 1); })
      .def_property_readonly("actor_count", &WorldString::actor_count)
      .def_property_readonly("empty", &WorldString::empty, "True for ε.")
      .def_property_readonly("alphabet", [](const WorldString& w) { return std::const_pointer_cast<Alphabet>(w.alphabet_ptr()); })
      .def("content_hash", &WorldString::content_hash,
           "A 64-bit hash of the content, stable across runs and machines (for determinism checks).")
      .def("nodes", [](const WorldString& w) {
        py::list out;
        for (std::size_t i = 0; i < w.nodes().size(); ++i) {
          if (w.nodes()[i].kind != NodeKind::Close) out.append(node_to_python(w.node(i)));
        }
        return out;
      }, "The symbols in order (scope ends are not listed).")
      .def("actors", [](const WorldString& w) {
        py::list out;
        for (std::size_t i = 0; i < w.nodes().size(); ++i) {
          if (w.nodes()[i].kind == NodeKind::Actor) out.append(node_to_python(w.node(i)));
        }
        return out;
      }, "The actors in order.")
      .def("blobs", [](const WorldString& w) {
        py::dict out;
        for_each_blob(w, [&](const auto& blob) { out[py::str(blob_name(*blob).substr(1))] = blob_to_python(blob); });
        return out;
      }, "The blobs the string refers to, by name (what a snapshot stores beside the text).")
      .def("blob_slots", [](const WorldString& w) {
        py::list out;
        for_each_blob(w, [&](const auto& blob) { out.append(py::str(blob_name(*blob).substr(1))); });
        return out;
      }, "The names of the blobs the string holds, one for each blob-valued attribute or parameter in the string's order (a blob held twice is named twice). A recorder stores a changed blob against what its slot held the frame before.")
      .def("tree", [](const WorldString& w, bool figures) {
        // Nested plain-Python form: ("P", name, params) / ("A", name, params) / ("T", name, params, [children]),
        // and with figures=True ("F", [("P", name, params), ...]) for primitives side by side.
        py::list root;
        std::vector<py::list> stack{root};
        py::object figure = py::none();  // the list of the figure being built (figures=True)
        for (std::size_t i = 0; i < w.nodes().size(); ++i) {
          const Node& n = w.nodes()[i];
          if (n.kind == NodeKind::Close) {
            stack.pop_back();
            figure = py::none();
            continue;
          }
          const NodeView view = w.node(i);
          py::tuple params(n.value_count);
          for (std::size_t k = 0; k < n.value_count; ++k) params[k] = value_to_python(w.store(), view.value(k));
          const std::string& name = view.info().name;
          if (n.kind == NodeKind::Transformation) {
            py::list children;
            stack.back().append(py::make_tuple("T", name, params, children));
            stack.push_back(children);
          } else {
            py::tuple item = py::make_tuple(n.kind == NodeKind::Actor ? "A" : "P", name, params);
            py::list& level = stack.back();
            if (figures && n.joined) {
              if (figure.is_none()) {  // the primitive before becomes the figure's first
                py::list members;
                members.append(level[py::len(level) - 1]);
                level[py::len(level) - 1] = py::make_tuple("F", members);
                figure = members;
              }
              figure.cast<py::list>().append(item);
              continue;
            }
            level.append(item);
          }
          figure = py::none();
        }
        return root;
      }, py::arg("figures") = false,
      "The string as nested Python tuples: ('P'|'A', name, params) and ('T', name, params, children). A "
      "figure of primitives side by side (rule 6, 'Robot Lamp') is its primitives one by one, or with "
      "figures=True one ('F', [('P', name, params), ...]).");

  m.def("build_string", [](std::shared_ptr<Alphabet> a, py::object parts) {
         StringBuilder out(a);
         append_python(out, parts, "build_string");
         return out.finish();
       }, py::arg("alphabet"), py::arg("parts"),
       "A string from Python parts: text, vwg.String, actors, vwg.Sym, or lists of these.");
  m.def("evolve", [](const WorldString& w, py::object events, std::uint64_t frame, double time, std::uint64_t seed) {
         EventList list = events_from_python(w.alphabet_ptr(), events);
         py::gil_scoped_release release;
         return evolve(w, list, FrameContext{frame, time, seed});
       }, py::arg("w"), py::arg("events"), py::arg("frame") = FrameContext{}.frame, py::arg("time") = FrameContext{}.time,
       py::arg("seed") = FrameContext{}.seed,
       "η(w, S) (paper eq. 8): every actor takes the events of S it responds to, in order.");
  m.def("visualize", [](const WorldString& w, py::object events, std::uint64_t frame, double time, std::uint64_t seed) {
         EventList list = events_from_python(w.alphabet_ptr(), events);
         py::gil_scoped_release release;
         return visualize(w, list, FrameContext{frame, time, seed});
       }, py::arg("w"), py::arg("events"), py::arg("frame") = FrameContext{}.frame, py::arg("time") = FrameContext{}.time,
       py::arg("seed") = FrameContext{}.seed,
       "π(w, Z) (paper eq. 9): the displayable string for the visual events among `events`.");
  m.def("display", [](const WorldString& v, std::shared_ptr<Backend> backend) {
         if (!backend) throw SchemaError("backend", "is None");
         py::gil_scoped_release release;
         display(v, *backend);
       }, py::arg("v"), py::arg("backend"), "φ(v) (paper eq. 7) on a backend: α, β, δ in string order.");
}

}  // namespace vwg::bindings
