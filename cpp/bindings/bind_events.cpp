// vwg.Event (an event e^d_c: type, data, optional target) and vwg.FrameInfo (the time instant a
// generator or backend is called for).
#include <string>

#include "common.hpp"

namespace vwg::bindings {

namespace {

struct PyEvent {
  std::string type;
  std::optional<std::int64_t> target;
  py::dict fields;
  std::string text;  // canonical text when made from an event list, else empty
};

std::string event_repr(const PyEvent& e) {
  std::string out = "vwg.Event(" + std::string(py::repr(py::str(e.type)));
  if (e.target) out += ", target=" + std::to_string(*e.target);
  for (auto item : e.fields) out += ", " + std::string(py::str(item.first)) + "=" + std::string(py::repr(item.second));
  return out + ")";
}

}  // namespace

namespace {
py::object make_event(const EventView& e) {
  PyEvent out;
  const EventTypeInfo& info = e.info();
  out.type = info.name;
  if (e.has_target()) out.target = e.target();
  for (std::size_t k = 0; k < e.field_count(); ++k) out.fields[py::str(info.fields.params[k].name)] = value_to_python(e.store(), e.value(k));
  out.text = to_text(e);
  return py::cast(std::move(out));
}

/// The Python events of the last event list seen: every actor that receives an event gets the
/// same (immutable) object instead of a new one per call.
struct EventCache {
  std::uint64_t serial = 0;
  std::vector<py::object> objects;
};
}  // namespace

py::object event_to_python(const EventView& e) {
  PYBIND11_CONSTINIT static py::gil_safe_call_once_and_store<EventCache> storage;
  EventCache& cache = const_cast<EventCache&>(storage.call_once_and_store_result([] { return EventCache{}; }).get_stored());
  const EventList& list = e.list();
  if (cache.serial != list.serial() || cache.objects.size() != list.size()) {
    cache.serial = list.serial();
    cache.objects.assign(list.size(), py::object());
  }
  py::object& slot = cache.objects[e.index()];
  if (!slot) slot = make_event(e);
  return slot;
}

void emit_python(EventList& out, py::handle obj, const std::string& what) {
  if (PyUnicode_Check(obj.ptr())) {
    parse_event(out, obj.cast<std::string>(), "<" + what + ">");
    return;
  }
  if (!py::isinstance<PyEvent>(obj)) {
    throw SchemaError(what, "expected a vwg.Event or an event's text, got " + std::string(py::str(py::type::handle_of(obj).attr("__name__"))));
  }
  const PyEvent& e = obj.cast<const PyEvent&>();
  const Alphabet& A = out.alphabet();
  const auto id = A.find_event_type(e.type);
  if (!id) throw SchemaError(what, "unknown event type '" + e.type + "' (not in the alphabet)");
  const EventTypeInfo& info = A.event_type(*id);
  std::vector<std::optional<Datum>> slots(info.fields.params.size());
  for (auto item : e.fields) {
    const std::string key = py::str(item.first);
    const int k = info.fields.index_of(key);
    if (k < 0) {
      std::string names;
      for (const auto& p : info.fields.params) names += (names.empty() ? "" : ", ") + p.name;
      throw SchemaError(info.name + "." + key, "no such field (fields: " + (names.empty() ? std::string("none") : names) + ")");
    }
    slots[static_cast<std::size_t>(k)] = datum_from_python(item.second, &info.fields.params[static_cast<std::size_t>(k)], info.name + "." + key);
  }
  std::vector<Datum> fields;
  for (std::size_t k = 0; k < slots.size(); ++k) {
    if (slots[k]) {
      fields.push_back(std::move(*slots[k]));
    } else if (info.fields.params[k].default_value) {
      fields.push_back(*info.fields.params[k].default_value);
    } else {
      throw SchemaError(info.name + "." + info.fields.params[k].name, "missing (it has no default)");
    }
  }
  out.emit(*id, fields, e.target ? *e.target : kNoTarget);
}

EventList events_from_python(const std::shared_ptr<const Alphabet>& alphabet, py::handle events) {
  EventList list(alphabet);
  std::size_t i = 0;
  for (auto e : events) emit_python(list, e, "events[" + std::to_string(i++) + "]");
  return list;
}

py::object frame_to_python(const FrameInfo& info, std::shared_ptr<PyFrame>& holder) {
  holder = std::make_shared<PyFrame>(PyFrame{info.frame, info.time, info.dt, info.world});
  return py::cast(holder);
}

void init_events(py::module_& m) {
  py::class_<PyEvent>(m, "Event", R"doc(
An event e^d_c (paper §II.C): an event type d, data fields c, and optionally the ``id`` of the one
actor it is for (``target``; the text form writes it ``to=``). Untargeted events reach every actor
that responds to the type. Fields read as attributes: ``e.dist``.)doc")
      .def(py::init([](std::string type, std::optional<std::int64_t> target, py::kwargs fields) {
             PyEvent e;
             e.type = std::move(type);
             e.target = target;
             for (auto item : fields) e.fields[item.first] = item.second;
             return e;
           }),
           py::arg("type"), py::arg("target") = py::none())
      .def_readonly("type", &PyEvent::type)
      .def_readonly("target", &PyEvent::target, "The id of the actor the event is for, or None (all actors).")
      .def_property_readonly("fields", [](const PyEvent& e) { return py::dict(e.fields); }, "The data fields (a copy).")
      .def("__getattr__", [](const PyEvent& e, const std::string& name) -> py::object {
        if (!e.fields.contains(name)) {
          std::string names;
          for (auto item : e.fields) names += (names.empty() ? "" : ", ") + std::string(py::str(item.first));
          throw py::attribute_error("event '" + e.type + "' has no field '" + name + "' (fields: " + (names.empty() ? "none" : names) + ")");
        }
        return e.fields[py::str(name)];
      })
      .def("__eq__", [](const PyEvent& a, py::object other) {
        if (!py::isinstance<PyEvent>(other)) return false;
        const PyEvent& b = other.cast<const PyEvent&>();
        return a.type == b.type && a.target == b.target && a.fields.equal(b.fields);
      })
      .def("__repr__", &event_repr)
      .def("__str__", [](const PyEvent& e) { return e.text.empty() ? event_repr(e) : e.text; });

  py::class_<PyFrame, std::shared_ptr<PyFrame>>(m, "FrameInfo", "The time instant t a generator or backend is called for.")
      .def_readonly("frame", &PyFrame::frame, "t: the frame number, from 0.")
      .def_readonly("time", &PyFrame::time, "Simulated seconds: frame * dt.")
      .def_readonly("dt", &PyFrame::dt, "Seconds per frame.")
      .def_property_readonly("world", [](const PyFrame& f) {
        if (!f.world) throw SchemaError("FrameInfo.world", "is only available during the call it was passed to");
        return WorldString(*f.world);
      }, "A copy of the string w of this frame (only during the call).")
      .def("__repr__", [](const PyFrame& f) {
        return "vwg.FrameInfo(frame=" + std::to_string(f.frame) + ", time=" + format_real(f.time) + ")";
      });
}

}  // namespace vwg::bindings
