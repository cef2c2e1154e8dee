// An actor type written in Python: λ handlers `on_<event>(self, e)`, θ handlers
// `show_<event>(self, e)`, optional run λ handlers `on_<event>_run(self, events)` that receive a
// run of events (a scan) as numpy columns, and optional batch λ handlers
// `on_<event>_batch(cls, actors, e)` that receive numpy columns of all the actors of the type.
#include <span>
#include <string>

#include "common.hpp"
#include "python_budget.hpp"

namespace vwg::bindings {

namespace {

/// λ and θ of one Python actor class. Holds Python objects, so it releases them with the GIL.
class PythonActor final : public ActorBehavior {
 public:
  struct Handler {
    py::object fn;
    bool wants_context = false;
  };

  PythonActor(const Alphabet& alphabet, py::object cls, py::dict on, py::dict show, py::dict batch, py::dict run)
      : cls_(std::move(cls)), name_(py::str(cls_.attr("name"))) {
    on_.resize(alphabet.event_type_count());
    show_.resize(alphabet.event_type_count());
    batch_.resize(alphabet.event_type_count());
    run_.resize(alphabet.event_type_count());
    auto fill = [&](py::dict handlers, std::vector<Handler>& into, bool visual_only) {
      for (auto item : handlers) {
        const std::string event = py::str(item.first);
        const EventTypeId id = alphabet.event_type_id(event);
        if (visual_only && !alphabet.event_type(id).visual) {
          throw SchemaError(name_ + ".show_" + event, "'" + event + "' is not a visual event type; θ handlers are for visual events");
        }
        py::tuple spec = py::reinterpret_borrow<py::tuple>(item.second);
        into[id] = Handler{spec[0], spec[1].cast<bool>()};
      }
    };
    fill(on, on_, false);
    fill(show, show_, true);
    fill(batch, batch_, false);
    fill(run, run_, false);
    batched_ = py::len(batch) > 0;
    if (batched_ && py::len(run) > 0) {
      throw SchemaError(name_, "has both batch handlers (on_<event>_batch) and run handlers (on_<event>_run); a class takes one or the other");
    }
    for (auto item : run) {
      const std::string event = py::str(item.first);
      for (const ParamSpec& spec : alphabet.event_type(alphabet.event_type_id(event)).fields.params) {
        if (spec.kind != ValueKind::Int && spec.kind != ValueKind::Real && spec.kind != ValueKind::Bool) {
          throw SchemaError(name_ + ".on_" + event + "_run",
                            "'" + event + "." + spec.name + "' is text or a blob: a run comes as columns of numbers and bools");
        }
      }
    }
    for (auto name : cls_.attr("_attribute_names")) attribute_names_.push_back(py::str(name));
    new_ = py::module_::import("builtins").attr("object").attr("__new__");
    actor_base_ = python_class("vwg.model.actor", "Actor");
    context_class_ = python_class("vwg.model.actor", "Context");
  }

  ~PythonActor() override {
    // The last reference may go from C++ code that released the GIL.
    if (!Py_IsInitialized()) {
      release_without_gil();
      return;
    }
    py::gil_scoped_acquire gil;
    on_.clear();
    show_.clear();
    batch_.clear();
    run_.clear();
    cls_ = py::object();
    new_ = py::object();
    actor_base_ = py::object();
    context_class_ = py::object();
  }

  void evolve(ActorState& self, const EventView& e, const EvolutionContext& ctx, Replacement& out) override {
    if (takes_runs(e.type())) {  // a run of one
      const auto at = static_cast<std::uint32_t>(e.index());
      evolve_run(self, e.list(), std::span<const std::uint32_t>(&at, 1), ctx, out);
      return;
    }
    const Handler* h = e.type() < on_.size() && on_[e.type()].fn ? &on_[e.type()] : nullptr;
    if (!h) return;  // responds to the type but defines no λ for it: unchanged
    py::gil_scoped_acquire gil;
    PythonCallTimer timer([&] { return "the Python actor's λ " + name_ + ".on_" + std::string(e.info().name); });
    py::object instance = make_instance(self);
    py::object event = event_to_python(e);
    py::object result = h->wants_context ? h->fn(instance, event, make_context(ctx)) : h->fn(instance, event);
    if (result.ptr() == instance.ptr()) return;  // `return self`: unchanged
    const std::string what = name_ + ".on_" + e.info().name;
    if (same_type(result)) {
      read_back(self, result, what);  // still one actor of this type
      return;
    }
    append_python(out.replace(), result, what);
  }

  void visualize(const ActorState& self, const EventView& e, const EvolutionContext& ctx, StringBuilder& out) override {
    const Handler* h = e.type() < show_.size() && show_[e.type()].fn ? &show_[e.type()] : nullptr;
    if (!h) return;  // ε
    py::gil_scoped_acquire gil;
    PythonCallTimer timer([&] { return "the Python actor's θ " + name_ + ".show_" + std::string(e.info().name); });
    py::object instance = make_instance(self);
    py::object event = event_to_python(e);
    py::object result = h->wants_context ? h->fn(instance, event, make_context(ctx)) : h->fn(instance, event);
    append_python(out, result, name_ + ".show_" + e.info().name);
  }

  bool batched() const override { return batched_; }

  bool takes_runs(EventTypeId type) const override { return type < run_.size() && run_[type].fn; }

  void evolve_run(ActorState& self, const EventList& events, std::span<const std::uint32_t> at, const EvolutionContext& ctx,
                  Replacement& out) override {
    (void)out;
    const EventTypeId type = events[at.front()].type();
    const Handler& h = run_[type];
    const std::string what = name_ + ".on_" + events.alphabet().event_type(type).name + "_run";
    py::gil_scoped_acquire gil;
    PythonCallTimer timer([&] { return "the Python actor's λ " + what; });
    py::object instance = make_instance(self);
    py::object run = event_run_to_python(events, at);
    py::object result = h.wants_context ? h.fn(instance, run, make_context(ctx)) : h.fn(instance, run);
    if (result.ptr() == instance.ptr()) return;  // `return self`: unchanged
    if (!same_type(result)) {
      throw SchemaError(what, "returned " + std::string(py::str(py::repr(result))) +
                                  "; a run handler returns self or self.with_(...): the actor stays one " + name_);
    }
    read_back(self, result, what);
  }

  void evolve_batch(ActorBatch& batch, const EventView& e, const EvolutionContext& ctx) override;

 private:
  bool same_type(py::handle result) const {
    return py::type::handle_of(result).is(cls_) || (PyObject_IsInstance(result.ptr(), actor_base_.ptr()) == 1 &&
                                                    std::string(py::str(py::type::handle_of(result).attr("name"))) == name_);
  }

  /// The attributes of `result`, an actor of this type, into the state.
  void read_back(ActorState& self, py::handle result, const std::string& what) const {
    py::tuple values = result.attr("_v");
    const Schema& schema = self.info().schema;
    if (py::len(values) != schema.params.size()) throw SchemaError(what, "returned an actor with the wrong number of attributes");
    for (std::size_t k = 0; k < schema.params.size(); ++k) {
      self.set(k, datum_from_python(values[k], &schema.params[k], name_ + "." + schema.params[k].name));
    }
  }

  py::object make_instance(const ActorState& state) const {
    py::tuple values(state.size());
    for (std::size_t k = 0; k < state.size(); ++k) values[k] = value_to_python(state.store(), state.value(k));
    py::object obj = new_(cls_);
    // Actors are frozen for users; set the values under the class's __setattr__.
    if (PyObject_GenericSetAttr(obj.ptr(), py::str("_v").ptr(), values.ptr()) != 0) throw py::error_already_set();
    return obj;
  }

  py::object make_context(const EvolutionContext& ctx) const { return context_class_(ctx.frame, ctx.time, ctx.seed); }

  void release_without_gil() {
    // At interpreter exit the objects cannot be released safely; leave them to the OS.
    for (auto* v : {&on_, &show_, &batch_, &run_}) {
      for (auto& h : *v) h.fn.release();
    }
    cls_.release();
    new_.release();
    actor_base_.release();
    context_class_.release();
  }

  py::object cls_;
  std::string name_;
  std::vector<Handler> on_, show_, batch_, run_;
  std::vector<std::string> attribute_names_;
  bool batched_ = false;
  py::object new_, actor_base_, context_class_;
};

/// The columns of a batch seen from Python: `actors["x"]` or `actors.x` is a numpy view of one
/// numeric attribute over all the actors of the batch; writing it changes them.
struct PyActorBatch {
  std::vector<std::string> names;
  ActorBatch batch;
};

py::object column(py::object self, const std::string& name) {
  const PyActorBatch& b = self.cast<const PyActorBatch&>();
  for (std::size_t j = 0; j < b.names.size(); ++j) {
    if (b.names[j] != name) continue;
    const py::ssize_t n = static_cast<py::ssize_t>(b.batch.count);
    // The array's base is the batch view, which holds the column: no copy, no dangling pointer.
    if (b.batch.ints[j]) return py::array_t<std::int64_t>({n}, {sizeof(std::int64_t)}, b.batch.ints[j]->data(), self);
    if (b.batch.reals[j]) return py::array_t<double>({n}, {sizeof(double)}, b.batch.reals[j]->data(), self);
    if (b.batch.bools[j]) {
      return py::array(py::dtype("bool"), std::vector<py::ssize_t>{n}, std::vector<py::ssize_t>{1}, b.batch.bools[j]->data(), self);
    }
    throw py::key_error("attribute '" + name + "' is text or a blob; batch handlers see int, float and bool attributes");
  }
  throw py::key_error("no attribute '" + name + "'");
}

void PythonActor::evolve_batch(ActorBatch& batch, const EventView& e, const EvolutionContext& ctx) {
  const Handler& h = batch_[e.type()];
  if (!h.fn) {
    throw SchemaError(name_ + ".on_" + e.info().name + "_batch",
                      "missing: an actor with batch handlers needs one for every event it responds to");
  }
  py::gil_scoped_acquire gil;
  py::object view = py::cast(PyActorBatch{attribute_names_, batch});  // shares the columns
  py::object event = event_to_python(e);
  if (h.wants_context) {
    h.fn(view, event, make_context(ctx));
  } else {
    h.fn(view, event);
  }
}

}  // namespace

void init_actors(py::module_& m) {
  py::class_<PythonActor, ActorBehavior, std::shared_ptr<PythonActor>>(m, "PythonActor",
                                                                        "λ and θ of an actor class written in Python (see vwg.Actor).")
      .def(py::init<const Alphabet&, py::object, py::dict, py::dict, py::dict, py::dict>(), py::arg("alphabet"), py::arg("cls"),
           py::arg("on"), py::arg("show"), py::arg("batch"), py::arg("run"),
           "Handlers by event type name: {event: (function, wants_context)}.");

  py::class_<PyActorBatch>(m, "ActorBatch", R"doc(
All the actors of one type that receive an event, as numpy columns: ``actors.x`` (or ``actors["x"]``)
is a writable view of attribute x over the batch, in string order. Only int, float and bool
attributes are columns.)doc")
      .def("__len__", [](const PyActorBatch& b) { return b.batch.count; })
      .def_property_readonly("names", [](const PyActorBatch& b) { return b.names; })
      .def("__getitem__", [](py::object self, const std::string& name) { return column(self, name); })
      .def("__getattr__", [](py::object self, const std::string& name) {
        try {
          return column(self, name);
        } catch (const py::key_error& e) {
          throw py::attribute_error(e.what());
        }
      });
}

}  // namespace vwg::bindings
