// Small actors and alphabets for the C++ tests; expected strings are written by hand in each test.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "vwg/vwg.hpp"

namespace vwg::testing {

/// An actor behavior made of two lambdas.
class LambdaActor : public ActorBehavior {
 public:
  using Evolve = std::function<void(ActorState&, const EventView&, const EvolutionContext&, Replacement&)>;
  using Show = std::function<void(const ActorState&, const EventView&, StringBuilder&)>;
  explicit LambdaActor(Evolve evolve, Show show = {}) : evolve_(std::move(evolve)), show_(std::move(show)) {}
  void evolve(ActorState& self, const EventView& e, const EvolutionContext& ctx, Replacement& out) override {
    evolve_(self, e, ctx, out);
  }
  void visualize(const ActorState& self, const EventView& e, const EvolutionContext&, StringBuilder& out) override {
    if (show_) show_(self, e, out);
  }

 private:
  Evolve evolve_;
  Show show_;
};

inline Schema schema(std::initializer_list<ParamSpec> params) { return Schema{params, false}; }
inline ParamSpec real(std::string name, std::optional<double> def = std::nullopt) {
  return ParamSpec{std::move(name), ValueKind::Real, def ? std::optional<Datum>(Datum(*def)) : std::nullopt};
}
inline ParamSpec integer(std::string name, std::optional<std::int64_t> def = std::nullopt) {
  return ParamSpec{std::move(name), ValueKind::Int, def ? std::optional<Datum>(Datum(*def)) : std::nullopt};
}

/// Parse with the alphabet, print back: the canonical text of `text`.
inline std::string canon(const std::shared_ptr<const Alphabet>& a, std::string_view text) {
  return to_text(parse_string(a, text));
}

}  // namespace vwg::testing
