// Event generators C^d : Time → (E^D)* (paper eq. 10). The engine asks each generator, in its
// priority order, for the frame's events; earlier generators' events come first in S.
#pragma once

#include <cstdint>
#include <string>

#include "vwg/event.hpp"
#include "vwg/state.hpp"
#include "vwg/world_string.hpp"

namespace vwg {

/// The time instant a generator is asked about.
struct FrameInfo {
  std::uint64_t frame = 0;  ///< t in the system algorithm
  double time = 0.0;        ///< simulated seconds: frame * dt
  double dt = 0.1;          ///< seconds per frame
  /// For a generator, the string w the events will be applied to; for a backend, the string the
  /// frame made (w_next: λ may have changed w's large attributes in place by then).
  const WorldString* world = nullptr;
};

class Generator {
 public:
  virtual ~Generator() = default;
  /// Append this frame's events to `out` (zero, one or several).
  virtual void generate(const FrameInfo& frame, EventList& out) = 0;
  /// Called once before the first frame with a seed derived from the engine's seed and the
  /// generator's position, so random generators are reproducible.
  virtual void reset(std::uint64_t seed) { (void)seed; }
  /// True if generate() may run at the same time as other concurrent generators' (on the engine's
  /// threads): it reads only what no generator changes during the frame and writes only its own
  /// state and `out`. A run of such generators fills S in the same order as on one thread. The
  /// default, false, runs it alone on the engine's thread.
  virtual bool concurrent() const { return false; }
  /// A short name for messages ("every_frame(tick)", "gLaser").
  virtual std::string name() const { return "generator"; }
  /// What decides its future events (random streams, timers, pending orders), for a saved run
  /// (vwg/state.hpp); a generator that keeps nothing writes nothing. The default refuses, naming
  /// the generator: one that does not say what it keeps cannot be saved.
  virtual void save_state(StateWriter& out) const;
  /// Back to what save_state() wrote (after reset(), before the first frame of a resumed run).
  virtual void load_state(StateReader& in);
};

/// One event of a fixed type (and fields) every frame: the paper's gDecide and gExecute.
class EveryFrameGenerator final : public Generator {
 public:
  /// Fields are checked against the event type's schema here, not every frame.
  EveryFrameGenerator(const Alphabet& alphabet, std::string_view type,
                      std::vector<Datum> fields = {}, std::int64_t target = kNoTarget);
  void generate(const FrameInfo& frame, EventList& out) override;
  std::string name() const override;
  void save_state(StateWriter&) const override {}  // the same event every frame: nothing to keep
  void load_state(StateReader& in) override { in.end(); }

 private:
  EventTypeId type_;
  std::vector<Datum> fields_;
  std::int64_t target_;
  std::string name_;
};

}  // namespace vwg
