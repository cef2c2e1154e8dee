// vwg.Event (an event e^d_c: type, data, optional target) and vwg.FrameInfo (the time instant a
// generator or backend is called for).
#include <algorithm>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "common.hpp"

namespace vwg::bindings {

namespace {

struct PyEvent {
  std::string type;
  std::optional<std::int64_t> target;
  py::dict fields;
  std::string text;  // canonical text when made from an event list, else empty
};

/// A batch of events of one type and target given by columns (vwg.EventColumns): one array a
/// field, one value an event. Each column is a read-only array owned here: float64 when made in
/// Python; float64, int64 or bool when it shows a run of events to an actor's run handler.
struct PyEventColumns {
  std::string type;
  std::optional<std::int64_t> target;
  std::vector<std::pair<std::string, py::array>> columns;  // in the order given
  std::size_t size() const { return columns.empty() ? 0 : static_cast<std::size_t>(columns.front().second.size()); }
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

namespace {

std::string field_names(const EventTypeInfo& info) {
  std::string names;
  for (const auto& p : info.fields.params) names += (names.empty() ? "" : ", ") + p.name;
  return names.empty() ? std::string("none") : names;
}

void emit_columns_python(EventList& out, const PyEventColumns& batch, const std::string& what) {
  const auto id = out.alphabet().find_event_type(batch.type);
  if (!id) throw SchemaError(what, "unknown event type '" + batch.type + "' (not in the alphabet)");
  const EventTypeInfo& info = out.alphabet().event_type(*id);
  std::vector<std::span<const double>> columns(info.fields.params.size());
  std::vector<py::array_t<double>> reals;  // the columns as float64 (a run's int columns are not)
  reals.reserve(batch.columns.size());
  std::vector<bool> given(columns.size(), false);
  for (const auto& [name, array] : batch.columns) {
    const int k = info.fields.index_of(name);
    if (k < 0) throw SchemaError(info.name + "." + name, "no such field (fields: " + field_names(info) + ")");
    reals.push_back(py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array));
    if (!reals.back()) throw SchemaError(info.name + "." + name, "expected reals");
    columns[static_cast<std::size_t>(k)] = std::span<const double>(reals.back().data(), static_cast<std::size_t>(reals.back().size()));
    given[static_cast<std::size_t>(k)] = true;
  }
  for (std::size_t k = 0; k < columns.size(); ++k) {
    if (!given[k]) throw SchemaError(info.name + "." + info.fields.params[k].name, "missing: a batch by columns gives every field");
  }
  out.emit_columns(*id, columns, batch.target ? *batch.target : kNoTarget);
}

}  // namespace

namespace {
/// Field k of the events at positions position(0) .. position(n - 1), as a float64, int64 or bool
/// array by the field's kind; None for a text or blob field.
template <class Position>
py::object field_column(const EventList& events, Position position, py::ssize_t n, std::size_t k, ValueKind kind) {
  auto gather = [&]<class T>(T Value::*member) -> py::array {
    py::array_t<T> a(n);
    T* d = a.mutable_data();
    for (py::ssize_t j = 0; j < n; ++j) d[j] = events[position(j)].value(k).*member;
    return a;
  };
  switch (kind) {
    case ValueKind::Real: return gather(&Value::r);
    case ValueKind::Int: return gather(&Value::i);
    case ValueKind::Bool: return gather(&Value::b);
    default: return py::none();
  }
}

/// "f", "i" or "b" for the kinds that come by columns; nullptr for text and blobs.
const char* column_kind(ValueKind kind) {
  switch (kind) {
    case ValueKind::Real: return "f";
    case ValueKind::Int: return "i";
    case ValueKind::Bool: return "b";
    default: return nullptr;
  }
}
}  // namespace

py::object event_run_to_python(const EventList& events, std::span<const std::uint32_t> at) {
  const EventView first = events[at.front()];
  const EventTypeInfo& info = first.info();
  PyEventColumns out;
  out.type = info.name;
  // Every event of a run reaches the actor: each is addressed to it or to all.
  bool targeted = true;
  for (const std::uint32_t i : at) targeted = targeted && events[i].has_target();
  if (targeted) out.target = first.target();
  const auto n = static_cast<py::ssize_t>(at.size());
  for (std::size_t k = 0; k < info.fields.params.size(); ++k) {
    const ParamSpec& spec = info.fields.params[k];
    py::object column = field_column(events, [&](py::ssize_t j) { return at[static_cast<std::size_t>(j)]; }, n, k, spec.kind);
    if (column.is_none()) {
      throw SchemaError(info.name + "." + spec.name, "is text or a blob: runs of events come as columns of numbers and bools");
    }
    column.attr("setflags")(py::arg("write") = false);
    out.columns.emplace_back(spec.name, std::move(column));
  }
  return py::cast(std::move(out));
}

py::list event_runs_to_python(const EventList& events, std::size_t min_run) {
  py::list out;
  const std::size_t n = events.size();
  std::size_t i = 0;
  while (i < n) {
    const EventView first = events[i];
    const EventTypeInfo& info = first.info();
    const bool numbers = std::all_of(info.fields.params.begin(), info.fields.params.end(),
                                     [](const ParamSpec& spec) { return column_kind(spec.kind) != nullptr; });
    std::size_t j = i + 1;
    while (numbers && j < n && events[j].type() == first.type() && events[j].has_target() == first.has_target()) ++j;
    if (!numbers || j - i < min_run) {
      for (; i < j; ++i) out.append(py::str(to_text(events[i])));
      continue;
    }
    const auto count = static_cast<py::ssize_t>(j - i);
    auto position = [i](py::ssize_t k) { return i + static_cast<std::size_t>(k); };
    py::object targets = py::none();
    if (first.has_target()) {
      py::array_t<std::int64_t> a(count);
      for (py::ssize_t k = 0; k < count; ++k) a.mutable_data()[k] = events[position(k)].target();
      targets = a;
    }
    py::list fields;
    for (std::size_t f = 0; f < info.fields.params.size(); ++f) {
      const ParamSpec& spec = info.fields.params[f];
      fields.append(py::make_tuple(spec.name, column_kind(spec.kind), field_column(events, position, count, f, spec.kind)));
    }
    out.append(py::make_tuple(info.name, j - i, targets, fields));
    i = j;
  }
  return out;
}

void emit_python(EventList& out, py::handle obj, const std::string& what) {
  if (PyUnicode_Check(obj.ptr())) {
    parse_event(out, obj.cast<std::string>(), "<" + what + ">");
    return;
  }
  if (py::isinstance<PyEventColumns>(obj)) {
    emit_columns_python(out, obj.cast<const PyEventColumns&>(), what);
    return;
  }
  if (!py::isinstance<PyEvent>(obj)) {
    throw SchemaError(what, "expected a vwg.Event, a vwg.EventColumns or an event's text, got " +
                                std::string(py::str(py::type::handle_of(obj).attr("__name__"))));
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
    if (k < 0) throw SchemaError(info.name + "." + key, "no such field (fields: " + field_names(info) + ")");
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

  py::class_<PyEventColumns>(m, "EventColumns", R"doc(
A batch of events of one type, all for the same actor (or all untargeted), given by columns: one
1-D array of reals a field, one value an event, e.g. a scan of 180 beams as
``vwg.EventColumns("eLaser", target=3, dist=ranges, angle=angles)``. A generator returns it among
its events; it stands for the events (dist[j], angle[j]) in order, and the engine stores them by
columns instead of one object a beam. Every field of the type must be a real and given; the arrays
are copied (as float64) and read-only here. A column reads as an attribute: ``events.dist``.

An actor's run handler ``on_<event>_run(self, events)`` receives the events of a run that reach it
in the same form (see vwg.Actor); there ``target`` is the actor's id if every event was addressed
to it, None if any was for all, and int and bool fields come as int64 and bool arrays.)doc")
      .def(py::init([](std::string type, std::optional<std::int64_t> target, py::kwargs columns) {
             PyEventColumns b;
             b.type = std::move(type);
             b.target = target;
             for (auto item : columns) {
               const std::string name = py::str(item.first);
               py::object converted;  // (a default array_t is an empty array, not none)
               if (!py::isinstance<py::str>(item.second) && !py::isinstance<py::bytes>(item.second)) {  // numpy reads text as no values
                 converted = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(item.second);
               }
               if (!converted || converted.cast<py::array>().ndim() != 1) {
                 throw SchemaError(b.type + "." + name, "expected a 1-D array of reals (one value an event), got " +
                                                            std::string(py::str(py::type::handle_of(item.second).attr("__name__"))) +
                                                            (converted ? " of " + std::to_string(converted.cast<py::array>().ndim()) + " dimensions"
                                                                       : std::string()));
               }
               // A copy of its own: the caller's array may change after.
               py::array array = py::array_t<double>(converted.cast<py::array_t<double>>().request());
               array.attr("setflags")(py::arg("write") = false);
               if (!b.columns.empty() && array.size() != b.columns.front().second.size()) {
                 throw SchemaError(b.type + "." + name, "has " + std::to_string(array.size()) + " values; " + b.columns.front().first +
                                                            " has " + std::to_string(b.columns.front().second.size()) +
                                                            " (one value an event in every column)");
               }
               b.columns.emplace_back(name, std::move(array));
             }
             if (b.columns.empty()) throw SchemaError(b.type, "EventColumns needs a column for each field, got none");
             return b;
           }),
           py::arg("type"), py::arg("target") = py::none())
      .def_readonly("type", &PyEventColumns::type)
      .def_readonly("target", &PyEventColumns::target, "The id of the actor the events are for, or None (all actors).")
      .def_property_readonly("columns", [](const PyEventColumns& b) {
        py::dict out;
        for (const auto& [name, array] : b.columns) out[py::str(name)] = array;
        return out;
      }, "The columns by field name (read-only arrays: float64, or int64 and bool for such fields of a run).")
      .def("__getattr__", [](const PyEventColumns& b, const std::string& name) -> py::object {
        for (const auto& [field, array] : b.columns) {
          if (field == name) return array;
        }
        std::string names;
        for (const auto& [field, array] : b.columns) names += (names.empty() ? "" : ", ") + field;
        throw py::attribute_error("events '" + b.type + "' have no field '" + name + "' (fields: " + names + ")");
      }, "A column by field name: ``events.dist``.")
      .def("__len__", &PyEventColumns::size, "The number of events.")
      .def("__repr__", [](const PyEventColumns& b) {
        std::string out = "vwg.EventColumns(" + std::string(py::repr(py::str(b.type)));
        if (b.target) out += ", target=" + std::to_string(*b.target);
        out += ", " + std::to_string(b.size()) + " events: ";
        for (std::size_t k = 0; k < b.columns.size(); ++k) out += (k ? ", " : "") + b.columns[k].first;
        return out + ")";
      });

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
