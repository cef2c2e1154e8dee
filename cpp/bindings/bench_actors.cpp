// A small actor written in C++ and usable from Python: for benchmarks (C++ λ versus Python λ on
// the same world) and as a check that C++ and Python actors give the same strings.
#include <string>

#include "common.hpp"

namespace vwg::bindings {

namespace {

/// Walker<x: real, v: real>: λ(step<dt>) moves x by v·dt; θ(show) is `<primitive><x>`.
class Walker final : public ActorBehavior {
 public:
  Walker(EventTypeId step, std::optional<EventTypeId> show, std::optional<SymbolId> primitive)
      : step_(step), show_(show), primitive_(primitive) {}
  void evolve(ActorState& self, const EventView& e, const EvolutionContext&, Replacement&) override {
    if (e.type() != step_) return;
    self.set_real(0, self.get_real(0) + self.get_real(1) * e.number(0));
  }
  void visualize(const ActorState& self, const EventView& e, const EvolutionContext&, StringBuilder& out) override {
    if (!show_ || e.type() != *show_ || !primitive_) return;
    const Datum x(self.get_real(0));
    out.primitive(*primitive_, std::span<const Datum>(&x, 1));
  }

 private:
  EventTypeId step_;
  std::optional<EventTypeId> show_;
  std::optional<SymbolId> primitive_;
};

}  // namespace

void init_bench_actors(py::module_& m) {
  m.def("walker_behavior", [](const Alphabet& a, const std::string& step, std::optional<std::string> show,
                              std::optional<std::string> primitive) -> std::shared_ptr<ActorBehavior> {
         const EventTypeId step_id = a.event_type_id(step);
         const auto& fields = a.event_type(step_id).fields.params;
         if (fields.empty() || fields[0].kind != ValueKind::Real) throw SchemaError(step, "needs a first field dt: float");
         std::optional<EventTypeId> show_id;
         if (show) show_id = a.event_type_id(*show);
         std::optional<SymbolId> prim;
         if (primitive) prim = a.symbol_id(*primitive, SymbolKind::Primitive);
         return std::make_shared<Walker>(step_id, show_id, prim);
       }, py::arg("alphabet"), py::arg("step"), py::arg("show") = py::none(), py::arg("primitive") = py::none(),
       R"doc(The behavior of a C++ actor type Walker<x: float, v: float>: λ(step<dt>) moves x by v·dt, and
θ(show) is `primitive<x>`. Register it with ``alphabet.add_actor(name, [step, show],
{"x": 0.0, "v": 1.0}, behavior)``.)doc");
}

}  // namespace vwg::bindings
