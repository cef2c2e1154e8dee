// Small actors and alphabets for the C++ tests; expected strings are written by hand in each test.
#pragma once

#include <cstdint>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>

#include "vwg/vwg.hpp"

namespace vwg::testing {

/// What the kernel says of the memory mapping that starts at `start` (/proc/self/smaps): its
/// "Anonymous:" size in bytes, the pages written privately (copied on write); -1 if no mapping
/// starts there.
inline long long anonymous_bytes(const void* start) {
  std::ifstream smaps("/proc/self/smaps");
  std::ostringstream want;
  want << std::hex << reinterpret_cast<std::uintptr_t>(start) << "-";
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    if (line.rfind(want.str(), 0) == 0) {
      inside = true;
    } else if (inside && line.rfind("Anonymous:", 0) == 0) {
      return std::stoll(line.substr(10)) * 1024;  // "Anonymous:      4 kB"
    }
  }
  return -1;
}

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
