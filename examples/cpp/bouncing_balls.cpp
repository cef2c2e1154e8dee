// Embedding the vwg engine in a C++ application: a C++ actor type, a C++ generator, a C++
// backend, and the system algorithm running frames. Exits non-zero if the result is not the one
// worked out by hand below, so the build of this example is also a test of the installed package.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <vwg/vwg.hpp>

namespace {

/// Ball<id, y, vy>: λ(gravity<g, dt>) falls with gravity and bounces on the floor y = 0 without
/// losing energy; θ(draw) is Translate<y>(Disc).
class Ball final : public vwg::ActorBehavior {
 public:
  explicit Ball(vwg::EventTypeId gravity) : gravity_(gravity) {}
  void evolve(vwg::ActorState& self, const vwg::EventView& e, const vwg::EvolutionContext&, vwg::Replacement&) override {
    if (e.type() != gravity_) return;  // λ sees every event of H, the visual `draw` too
    const double g = e.number(0), dt = e.number(1);
    double vy = self.get_real(2) - g * dt;
    double y = self.get_real(1) + vy * dt;
    if (y < 0.0) {  // bounce
      y = -y;
      vy = -vy;
    }
    self.set_real(1, y);
    self.set_real(2, vy);
  }
  void visualize(const vwg::ActorState& self, const vwg::EventView&, const vwg::EvolutionContext&,
                 vwg::StringBuilder& out) override {
    out.open("Translate", {self.get_real(1)}).primitive("Disc").close();
  }

 private:
  vwg::EventTypeId gravity_;
};

/// gravity<g, dt> every frame.
class Gravity final : public vwg::Generator {
 public:
  void generate(const vwg::FrameInfo& frame, vwg::EventList& out) override { out.emit("gravity", {9.81, frame.dt}); }
  std::string name() const override { return "gravity"; }
};

/// Counts discs and remembers the lowest height drawn.
class Stats final : public vwg::Backend {
 public:
  void open(const vwg::NodeView& t) override { height_ = t.number(0); }
  void close(const vwg::NodeView&) override {}
  void primitive(const vwg::NodeView&) override {
    ++discs;
    lowest = std::min(lowest, height_);
  }
  int discs = 0;
  double lowest = 1e9;

 private:
  double height_ = 0.0;
};

}  // namespace

int run() {
  auto alphabet = std::make_shared<vwg::Alphabet>();
  alphabet->add_primitive("Disc");
  alphabet->add_transformation("Translate", vwg::Schema{{{"y", vwg::ValueKind::Real, std::nullopt}}, false});
  alphabet->add_event_type("gravity", false, vwg::Schema{{{"g", vwg::ValueKind::Real, std::nullopt},
                                                          {"dt", vwg::ValueKind::Real, std::nullopt}}, false});
  alphabet->add_event_type("draw", true);
  alphabet->add_actor("Ball", {"gravity", "draw"},
                      vwg::Schema{{{"id", vwg::ValueKind::Int, vwg::Datum(0)},
                                   {"y", vwg::ValueKind::Real, std::nullopt},
                                   {"vy", vwg::ValueKind::Real, vwg::Datum(0.0)}}, false},
                      std::make_shared<Ball>(alphabet->event_type_id("gravity")));

  vwg::WorldString w = vwg::parse_string(alphabet, "Ball<id=1, y=10.0> . Ball<id=2, y=5.0>", "example");
  auto stats = std::make_shared<Stats>();
  vwg::Engine engine(std::move(w),
                     {std::make_shared<Gravity>(), std::make_shared<vwg::EveryFrameGenerator>(*alphabet, "draw")},
                     stats, vwg::EngineOptions{0.01, 0});
  engine.run(1000);

  std::printf("vwg %s: %llu frames, %d discs drawn, lowest %.3f m\n  %s\n", VWG_VERSION,
              static_cast<unsigned long long>(engine.frame()), stats->discs, stats->lowest,
              vwg::to_text(engine.string()).c_str());

  // Hand check: two balls drawn each of 1000 frames; energy is kept by the bounce, so each ball's
  // height stays within [0, its drop height] and its speed below sqrt(2 g h) plus one step of g·dt.
  bool ok = engine.frame() == 1000 && stats->discs == 2000 && stats->lowest >= 0.0;
  const double drops[] = {10.0, 5.0};
  for (int k = 0; k < 2; ++k) {
    const vwg::NodeView ball = engine.string().node(static_cast<std::size_t>(k));
    const double y = ball.number(1), vy = ball.number(2);
    ok = ok && y >= 0.0 && y <= drops[k] + 1e-9 && std::abs(vy) <= std::sqrt(2 * 9.81 * drops[k]) + 9.81 * 0.01 + 1e-9;
  }
  if (!ok) {
    std::fprintf(stderr, "unexpected result\n");
    return 1;
  }
  return 0;
}

int main() {
  try {
    return run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
