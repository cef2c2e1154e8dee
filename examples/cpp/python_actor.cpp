// A C++ application that hosts Python: the engine is vwg's C++ core (vwg::core, from the C++ SDK of
// the wheel or of a source install), and one actor's λ is written in Python, run by an interpreter
// embedded in the program (pybind11's embed). The Python side is plain Python: λ gets the actor's
// attributes and the event's fields as numbers and returns the new attributes, so it needs no vwg
// module of its own (the program links vwg; a second copy imported into Python would be another world).
//
//   Counter<n, total>  responding to  add<k>:  λ in Python:  n + 1, total + k
//
// Exits non-zero unless the result is the one worked out by hand below.
#include <pybind11/embed.h>

#include <cstdio>
#include <memory>
#include <string>

#include <vwg/vwg.hpp>

namespace py = pybind11;

namespace {

/// λ(Counter, add<k>) by a Python function lam(n, total, k) -> (n, total).
class PythonLambda final : public vwg::ActorBehavior {
 public:
  explicit PythonLambda(py::object lam) : lam_(std::move(lam)) {}
  void evolve(vwg::ActorState& self, const vwg::EventView& e, const vwg::EvolutionContext&, vwg::Replacement&) override {
    const py::tuple out = lam_(self.get_int(0), self.get_int(1), static_cast<std::int64_t>(e.number(0)));
    self.set_int(0, out[0].cast<std::int64_t>());
    self.set_int(1, out[1].cast<std::int64_t>());
  }

 private:
  py::object lam_;
};

/// add<k = frame number> every frame.
class Adds final : public vwg::Generator {
 public:
  void generate(const vwg::FrameInfo& frame, vwg::EventList& out) override {
    out.emit("add", {static_cast<std::int64_t>(frame.frame)});
  }
  std::string name() const override { return "adds"; }
};

}  // namespace

int main() {
  const py::scoped_interpreter python;  // the interpreter lives as long as this program's main
  try {
    // λ, written in Python (a module of the application would do as well: py::module_::import).
    py::dict scope;
    py::exec(R"py(
def lam(n, total, k):
    return n + 1, total + k
)py", py::globals(), scope);

    auto alphabet = std::make_shared<vwg::Alphabet>();
    alphabet->add_event_type("add", false, vwg::Schema{{{"k", vwg::ValueKind::Int, std::nullopt}}, false});
    alphabet->add_actor("Counter", {"add"},
                        vwg::Schema{{{"n", vwg::ValueKind::Int, vwg::Datum(std::int64_t{0})},
                                     {"total", vwg::ValueKind::Int, vwg::Datum(std::int64_t{0})}}, false},
                        std::make_shared<PythonLambda>(scope["lam"]));
    vwg::Engine engine(vwg::parse_string(alphabet, "Counter<n=0, total=0>", "example"), {std::make_shared<Adds>()},
                       nullptr, vwg::EngineOptions{0.1, 0, 0, 0, 1});
    engine.run(100);
    const std::string text = vwg::to_text(engine.string());
    std::printf("vwg %s, Python %s: %s\n", VWG_VERSION, PY_VERSION, text.c_str());
    // By hand: 100 frames, k = 0 + 1 + ... + 99 = 4950.
    if (text != "Counter<n=100, total=4950>") {
      std::fprintf(stderr, "unexpected result\n");
      return 1;
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
