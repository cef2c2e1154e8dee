// The system algorithm (paper §II.D):
//   w = w0; t = 0
//   while w ≠ ε:  S = events of all generators in priority order;  Z = visual events of S
//                 w_next = η(w, S);  v = π(w, Z);  φ(v, G);  w = w_next;  t = t + 1
// A frame is all or nothing: if any step throws, w and t stay as they were after the last
// complete frame.
#pragma once

#include <atomic>
#include <concepts>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "vwg/backend.hpp"
#include "vwg/event.hpp"
#include "vwg/generator.hpp"
#include "vwg/semantics.hpp"
#include "vwg/text.hpp"
#include "vwg/world_string.hpp"

namespace vwg {

struct EngineOptions {
  double dt = 0.1;          ///< simulated seconds per frame
  std::uint64_t seed = 0;   ///< fixes every random choice of generators and actors
  std::uint64_t first_frame = 0;  ///< t of the first frame (a replay starts where its record did)
  /// A frame whose next string would have more symbols than this fails with a FrameError instead
  /// of exhausting memory (a world that spawns without bound); 0: no limit.
  std::uint64_t max_symbols = 0;
  /// Threads for the frame's independent work: the concurrent() generators (each robot's laser)
  /// and the λ of concurrent() actors (each robot). 0: the machine's cores. Any count gives the
  /// same frames.
  unsigned threads = 0;
};

/// Simulated seconds per frame a run may have, from a microsecond to an hour: world files, the
/// command line, records and the engine take this one range (below it, a scripted order's frame
/// number time / dt leaves 64 bits).
inline constexpr double kMinDt = 1e-6;
inline constexpr double kMaxDt = 3600.0;

/// Throws SchemaError(field) for a dt that is not a number of seconds in [kMinDt, kMaxDt].
void check_dt(double dt, const std::string& field = "dt");

/// Each field with its name and meaning (vwg.EngineOptions in Python).
template <class S, class F>
  requires std::same_as<std::remove_const_t<S>, EngineOptions>
void visit_settings(S& s, F&& field) {
  field("dt", s.dt, "simulated seconds per frame");
  field("seed", s.seed, "fixes every random choice of generators and actors");
  field("first_frame", s.first_frame, "t of the first frame (a replay starts where its record did)");
  field("max_symbols", s.max_symbols, "a frame whose string would have more symbols fails (0: no limit)");
  field("threads", s.threads, "threads for the frame's independent work (0: the machine's cores)");
}

/// Throws SchemaError naming `owner.field`: a dt outside [kMinDt, kMaxDt] (check_dt), more threads
/// than kMaxThreads.
void check_settings(const EngineOptions& options, const std::string& owner);

/// What one frame did, handed to frame observers (recorders, viewers) after the frame completes:
/// its events and the string they made. The string at its start is the previous frame's `after`
/// (or the initial string); it is not kept, since λ may have changed its large attributes in place.
struct FrameRecord {
  std::uint64_t frame;
  double time;
  const EventList& events;  ///< S
  const WorldString& after;  ///< w_next
};

/// What a run keeps in its engine, between frames, for a saved run (vwg/state.hpp): the frame
/// number, w (its text and the blobs the text names, each once), and what each generator and each
/// actor type's behaviour keeps outside the string. The platform a run drives keeps its own
/// (RobotPlatform::save_state).
struct EngineState {
  std::uint64_t frame = 0;
  std::string string;  ///< the text form of w; blobs as @name
  BlobTable blobs;     ///< every blob the text names, by name (without its '@')
  std::vector<std::string> generators;  ///< save_state() of each generator, in priority order
  /// save_state() of the behaviour of each actor type of the alphabet that has one, by type name.
  std::vector<std::pair<std::string, std::string>> actors;
};

/// Why run() returned.
enum class StopReason { Empty, FrameLimit, Requested, Done };

/// When a run has done its job (every robot at its room, say): checked by run() after each frame,
/// in C++, so a run needs no per-frame call into Python to know when to stop.
class StopCondition {
 public:
  virtual ~StopCondition() = default;
  /// `w` is the string after the frame numbered `frame`.
  virtual bool done(const WorldString& w, std::uint64_t frame) = 0;
};

/// An engine is used by one thread at a time and is not re-entrant: step(), step_with(), run(),
/// set_string() and collect_events() called from inside one of its frames (a λ, θ, generator,
/// backend or observer) or while another thread is in one of them throw vwg::Error saying so,
/// instead of corrupting the string they read.
///
/// Reading is safe from any thread: string_copy(), last_events_copy(), add_observer() and
/// stop_when() called from another thread wait for the frame under way to end
/// (a frame holds the engine's state lock, a run takes it frame by frame, and a waiting reader gets
/// it before the next frame starts), so they never see a frame half done. From inside a frame they
/// act at once: the caller is the frame (Python's λ, θ and generators run on that thread). A
/// concurrent() actor or generator, on one of the frame's worker threads, must not call them (it
/// would wait for its own frame): it is handed what it needs. The references string() and
/// last_events() are for the thread that runs the frames.
class Engine {
 public:
  using Observer = std::function<void(const FrameRecord&)>;

  /// `generators` in priority order (first = highest). `backend` may be null (φ is skipped).
  Engine(WorldString initial, std::vector<std::shared_ptr<Generator>> generators,
         std::shared_ptr<Backend> backend, EngineOptions options = {});

  /// Run one frame; returns false (and does nothing) if w = ε.
  bool step();
  /// One frame with the given events instead of the generators' (replaying a record).
  bool step_with(const EventList& events);
  /// Run until w = ε, `max_frames` more frames have run, or request_stop() was called.
  StopReason run(std::uint64_t max_frames);
  /// Ask run() to stop after the current frame (safe from another thread or a callback). A
  /// request made between runs stops the next run after its first frame.
  void request_stop() { stop_requested_ = true; }
  /// run() returns StopReason::Done after a frame that leaves `condition` true (null: never).
  void stop_when(std::shared_ptr<StopCondition> condition);

  /// w, for the thread that runs the frames (another thread: string_copy()).
  const WorldString& string() const { return w_; }
  /// A copy of w between frames, from any thread.
  WorldString string_copy() const;
  /// Replace w (e.g. to load a snapshot); the frame counter is kept.
  void set_string(WorldString w);
  /// The run's state between frames, from any thread or from an observer (the frame is complete
  /// then); from a λ, θ, generator or backend it throws. Without `generators`, their states are left
  /// out (a real robot's run, whose links cannot be saved: its string and its robots' maps can).
  EngineState save_state(bool generators = true) const;
  /// Go on from `state`, saved by an engine made as this one was (the same alphabet, generators in
  /// the same order, actor types with the same behaviours): w, the frame number, the generators'
  /// and behaviours' states. Throws SchemaError naming the part that does not fit (and then
  /// changes nothing of w or the frame; generators already loaded keep their new state).
  void load_state(const EngineState& state);
  /// The number of frames completed, from any thread at once (an atomic read, no waiting): it counts
  /// a frame before that frame's observers run.
  std::uint64_t frame() const { return frame_.load(std::memory_order_acquire); }
  double time() const { return static_cast<double>(frame()) * options_.dt; }
  const EngineOptions& options() const { return options_; }
  /// The alphabet of w (fixed for the engine's life: safe from any thread).
  const std::shared_ptr<const Alphabet>& alphabet_ptr() const { return alphabet_; }
  /// S of the last frame, for the thread that runs the frames (another thread: last_events_copy()).
  const EventList& last_events() const { return last_events_; }
  /// A copy of the last frame's S between frames, from any thread.
  EventList last_events_copy() const;
  const std::shared_ptr<Backend>& backend() const { return backend_; }
  const std::vector<std::shared_ptr<Generator>>& generators() const { return generators_; }

  /// Called after every completed frame, in the order added. From inside a frame (an observer
  /// adding another) it throws: the frame is walking the list.
  void add_observer(Observer observer);

  /// The events the generators give for the current frame (used by step()).
  EventList collect_events();

 private:
  class Use;  // holds the engine for one call; see the class comment
  class Between;  // holds the state lock between frames for a reader (any thread)
  /// Held by a frame from its first read of w to its observers' end (and by set_string). A runner
  /// lets the readers that asked during a frame in before its next frame (fair_to_readers()).
  std::unique_lock<std::mutex> lock_state();
  void fair_to_readers() const;
  // Runs a frame on `events`, which become last_events_; `events` gets the list they replace, whose
  // buffers the next frame fills again (ten thousand lasers give millions of events a frame:
  // fresh buffers each frame were page faults and zeroed pages).
  bool run_frame(EventList& events);
  /// Clears `events` and fills it with the generators' events for this frame.
  void collect_events_unlocked(EventList& events);
  void generate(std::size_t k, const FrameInfo& info, EventList& out);  // generator k, failures located
  WorldString w_;
  std::shared_ptr<const Alphabet> alphabet_;  // w_'s, kept apart so that reading it needs no lock
  std::vector<std::shared_ptr<Generator>> generators_;
  std::shared_ptr<Backend> backend_;
  EngineOptions options_;
  std::atomic<std::uint64_t> frame_{0};
  EventList last_events_;
  EventList next_events_;              // the buffers the next frame's events are collected into
  std::vector<EventList> part_events_;  // the same, for each concurrent generator
  BlobJournal journal_;  // what the frame changed in place, undone if it fails
  std::vector<Observer> observers_;
  std::atomic<bool> stop_requested_{false};
  std::shared_ptr<StopCondition> stop_when_;
  std::mutex use_;
  std::atomic<std::thread::id> user_{};  // the thread inside a call, if any
  mutable std::mutex state_;  // w_, last_events_, observers_, stop_when_ between frames
  mutable std::atomic<std::uint64_t> reads_asked_{0}, reads_served_{0};
};

}  // namespace vwg
