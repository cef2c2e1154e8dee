#include "vwg/engine.hpp"

#include <optional>

#include <cmath>
#include <cstdio>
#include <string>
#include <unordered_map>
#include <utility>

#include "src/parallel.hpp"
#include "vwg/error.hpp"
#include "vwg/random.hpp"
#include "vwg/text.hpp"

namespace vwg {

void check_dt(double dt, const std::string& field) {
  if (!(dt >= kMinDt && dt <= kMaxDt)) {  // NaN fails both
    char range[64];
    std::snprintf(range, sizeof range, "%g to %g", kMinDt, kMaxDt);
    throw SchemaError(field, std::string("expected a number of seconds from ") + range + ", got " + format_real(dt));
  }
}

void check_settings(const EngineOptions& options, const std::string& owner) {
  check_dt(options.dt, owner + ".dt");
  if (options.threads > kMaxThreads) {
    throw SchemaError(owner + ".threads", "expected 0 (the machine's cores) to " + std::to_string(kMaxThreads) +
                                              " threads, got " + std::to_string(options.threads));
  }
}

class Engine::Use {
 public:
  Use(Engine& e, const char* what) : e_(e) {
    if (e_.user_.load() == std::this_thread::get_id()) {
      throw Error(std::string("Engine.") + what + ": called during a frame of the same engine (from a λ, θ, "
                  "generator, backend or observer); an engine is not re-entrant: request_stop() ends a run");
    }
    if (!e_.use_.try_lock()) {
      throw Error(std::string("Engine.") + what + ": the engine is running a frame in another thread; use one "
                  "engine from one thread at a time");
    }
    e_.user_ = std::this_thread::get_id();
  }
  ~Use() {
    e_.user_ = std::thread::id{};
    e_.use_.unlock();
  }
  Use(const Use&) = delete;
  Use& operator=(const Use&) = delete;

 private:
  Engine& e_;
};

class Engine::Between {
 public:
  explicit Between(const Engine& e) {
    if (e.user_.load() == std::this_thread::get_id()) return;  // called from inside a frame: the caller is the frame
    e.reads_asked_.fetch_add(1);
    lock_ = std::unique_lock<std::mutex>(e.state_);
    e.reads_served_.fetch_add(1);
  }

 private:
  std::unique_lock<std::mutex> lock_;
};

std::unique_lock<std::mutex> Engine::lock_state() { return std::unique_lock<std::mutex>(state_); }

void Engine::fair_to_readers() const {
  // A mutex is not fair: the runner would take it again before a waiting reader wakes, frame after
  // frame. The readers that asked before this point get it first; later ones cannot hold it back.
  const std::uint64_t asked = reads_asked_.load();
  while (reads_served_.load() < asked) std::this_thread::yield();
}

WorldString Engine::string_copy() const {
  const Between between(*this);
  return w_;
}

EventList Engine::last_events_copy() const {
  const Between between(*this);
  return last_events_;
}

void Engine::add_observer(Observer observer) {
  if (user_.load() == std::this_thread::get_id()) {
    throw Error("Engine.add_observer: called during a frame of the same engine; add observers before or between runs");
  }
  const Between between(*this);
  observers_.push_back(std::move(observer));
}

void Engine::stop_when(std::shared_ptr<StopCondition> condition) {
  if (user_.load() == std::this_thread::get_id()) {
    throw Error("Engine.stop_when: called during a frame of the same engine; set it before or between runs");
  }
  const Between between(*this);
  stop_when_ = std::move(condition);
}

Engine::Engine(WorldString initial, std::vector<std::shared_ptr<Generator>> generators,
               std::shared_ptr<Backend> backend, EngineOptions options)
    : w_(std::move(initial)), alphabet_(w_.alphabet_ptr()), generators_(std::move(generators)), backend_(std::move(backend)),
      options_(options), frame_(options.first_frame), last_events_(w_.alphabet_ptr()), next_events_(w_.alphabet_ptr()) {
  check_settings(options_, "EngineOptions");
  if (options_.threads == 0) options_.threads = default_threads();
  std::unordered_map<const Generator*, std::size_t> side_by_side;
  for (std::size_t k = 0; k < generators_.size(); ++k) {
    if (!generators_[k]) throw SchemaError("generators[" + std::to_string(k) + "]", "is null");
    // One that runs side by side with others must not run beside itself.
    if (generators_[k]->concurrent()) {
      if (const auto [at, fresh] = side_by_side.try_emplace(generators_[k].get(), k); !fresh) {
        throw SchemaError("generators[" + std::to_string(k) + "]", "'" + generators_[k]->name() +
                          "' is listed twice (also as generators[" + std::to_string(at->second) + "]); list each sensor once");
      }
    }
    generators_[k]->reset(derive_seed(options_.seed, 0x67656EULL, k));
  }
}

void Engine::set_string(WorldString w) {
  const Use use(*this, "set_string");
  if (w.alphabet_ptr() != alphabet_) throw Error("set_string: the string uses another alphabet");
  const auto state = lock_state();
  w_ = std::move(w);
}

namespace {
// The engine whose observers this thread is running: its frame is complete, so its state may be
// saved from there (a run that keeps a state every K frames).
thread_local const Engine* observed = nullptr;
}  // namespace

EngineState Engine::save_state(bool generators) const {
  if (user_.load() == std::this_thread::get_id() && observed != this) {
    throw Error("Engine.save_state: called during a frame of the same engine (from a λ, θ, generator or backend); "
                "save between frames or from an observer");
  }
  const Between between(*this);
  EngineState state;
  state.frame = frame();
  state.string = to_text(w_);
  const ValueStore& store = w_.store();
  for (const Node& node : w_.nodes()) {
    if (node.kind == NodeKind::Close) continue;
    for (std::uint32_t k = 0; k < node.value_count; ++k) {
      const Value& v = store[node.first_value + k];
      if (v.kind != ValueKind::Blob) continue;
      const std::shared_ptr<const Blob>& blob = store.blob(v);
      state.blobs.try_emplace(blob_name(*blob).substr(1), blob);  // the table's names have no '@'
    }
  }
  for (const auto& g : generators ? generators_ : std::vector<std::shared_ptr<Generator>>{}) {
    StateWriter out;
    g->save_state(out);
    state.generators.push_back(out.take());
  }
  for (std::size_t id = 0; id < alphabet_->symbol_count(); ++id) {
    const SymbolInfo& info = alphabet_->symbol(static_cast<SymbolId>(id));
    if (!info.behavior) continue;
    StateWriter out;
    info.behavior->save_state(out);
    state.actors.emplace_back(info.name, out.take());
  }
  return state;
}

void Engine::load_state(const EngineState& state) {
  const Use use(*this, "load_state");
  if (state.generators.size() != generators_.size()) {
    throw SchemaError("state.generators", "the saved run had " + std::to_string(state.generators.size()) +
                                              " generators; this one has " + std::to_string(generators_.size()));
  }
  WorldString w = parse_string(alphabet_, state.string, "<saved string>", &state.blobs);
  std::vector<std::shared_ptr<ActorBehavior>> behaviors;
  for (std::size_t id = 0; id < alphabet_->symbol_count(); ++id) {
    const SymbolInfo& info = alphabet_->symbol(static_cast<SymbolId>(id));
    if (info.behavior) behaviors.push_back(info.behavior);
  }
  if (state.actors.size() != behaviors.size()) {
    throw SchemaError("state.actors", "the saved run had " + std::to_string(state.actors.size()) +
                                          " actor types with a behaviour; this one has " + std::to_string(behaviors.size()));
  }
  for (std::size_t k = 0; k < generators_.size(); ++k) {
    StateReader in(state.generators[k], "state.generators[" + std::to_string(k) + "] (" + generators_[k]->name() + ")");
    generators_[k]->load_state(in);
  }
  std::size_t b = 0;
  for (std::size_t id = 0; id < alphabet_->symbol_count(); ++id) {
    const SymbolInfo& info = alphabet_->symbol(static_cast<SymbolId>(id));
    if (!info.behavior) continue;
    const auto& [name, bytes] = state.actors[b++];
    if (name != info.name) throw SchemaError("state.actors", "expected the actor type " + info.name + ", found " + name);
    StateReader in(bytes, "state.actors." + name);
    info.behavior->load_state(in);
  }
  const auto lock = lock_state();
  w_ = std::move(w);
  frame_.store(state.frame, std::memory_order_release);
  last_events_.clear();
}

EventList Engine::collect_events() {
  const Use use(*this, "collect_events");
  EventList events(w_.alphabet_ptr());
  const auto state = lock_state();
  collect_events_unlocked(events);
  return events;
}

void Engine::generate(std::size_t k, const FrameInfo& info, EventList& out) {
  try {
    generators_[k]->generate(info, out);
  } catch (...) {
    const std::exception_ptr cause = std::current_exception();
    throw FrameError(frame_, "generate", "", "", "generator " + std::to_string(k) + " '" + generators_[k]->name() + "'",
                     describe_exception(cause), cause);
  }
}

void Engine::collect_events_unlocked(EventList& events) {
  const Alphabet::FrameUse frozen(w_.alphabet());  // no names added while generators read them
  events.clear();
  const FrameInfo info{frame_, time(), options_.dt, &w_};
  const std::size_t n = generators_.size();
  for (std::size_t k = 0; k < n;) {
    // A run of concurrent generators (the robots' lasers) side by side, each into a list of its
    // own, appended in priority order: S is the same as on one thread.
    std::size_t end = k;
    while (end < n && generators_[end]->concurrent()) ++end;
    if (options_.threads > 1 && end - k >= 2) {
      std::vector<EventList>& parts = part_events_;
      if (parts.size() < end - k) parts.resize(end - k, EventList(w_.alphabet_ptr()));
      for (std::size_t j = 0; j < end - k; ++j) parts[j].clear();  // a generator that threw may have left some
      parallel_for(end - k, options_.threads, [&](std::size_t j) { generate(k + j, info, parts[j]); });
      EventList::Sizes room = events.sizes();
      for (std::size_t j = 0; j < end - k; ++j) room += parts[j].sizes();
      events.reserve(room);
      // Emptied once appended (their buffers stay): no event, and no blob it holds, is kept alive
      // by a buffer beyond its frame (a blob held twice is copied instead of written in place).
      for (std::size_t j = 0; j < end - k; ++j) events.append(parts[j]), parts[j].clear();
      k = end;
    } else {
      generate(k, info, events);
      ++k;
    }
  }
}

bool Engine::step() {
  const Use use(*this, "step");
  const auto state = lock_state();
  if (w_.empty()) return false;
  collect_events_unlocked(next_events_);
  return run_frame(next_events_);
}

bool Engine::step_with(const EventList& events) {
  const Use use(*this, "step_with");
  if (w_.empty()) return false;
  if (events.alphabet_ptr() != w_.alphabet_ptr()) throw Error("step_with: the events use another alphabet");
  EventList copy(events);
  const auto state = lock_state();
  return run_frame(copy);
}

bool Engine::run_frame(EventList& events) {
  const Alphabet::FrameUse frozen(w_.alphabet());  // no names added while the frame reads them
  const FrameContext ctx{frame_, time(), options_.seed};
  // η and π both read w. π runs first, since η may change w's large attributes in place; a
  // string with no actors is its own evolution and its own display.
  const bool has_actors = w_.actor_count() > 0;
  std::optional<WorldString> shown;
  if (backend_ && has_actors) shown = visualize(w_, events, ctx);
  journal_.clear();
  std::optional<WorldString> next;
  try {
    next.emplace(has_actors ? evolve_in_place(w_, events, ctx, journal_, options_.threads) : w_);
    if (options_.max_symbols && next->symbol_count() > options_.max_symbols) {
      throw FrameError(frame_, "evolve", "", "", "", "the string grew to " + std::to_string(next->symbol_count()) +
                       " symbols, over the limit of " + std::to_string(options_.max_symbols) +
                       " (max_symbols); raise the limit if this growth is intended", nullptr);
    }
    if (backend_) {
      const FrameInfo info{frame_, time(), options_.dt, &*next};
      std::string where = "backend '" + backend_->name() + "'";
      try {
        backend_->begin_frame(info);
        display(shown ? *shown : w_, *backend_);
        backend_->end_frame(info);
      } catch (...) {
        const std::exception_ptr cause = std::current_exception();
        throw FrameError(frame_, "display", "", "", where, describe_exception(cause), cause);
      }
    }
  } catch (...) {
    // All or nothing: w gets back what λ changed in place.
    next.reset();
    journal_.rollback();
    throw;
  }
  // The frame is complete: commit it, then tell the observers (a failing recorder does not undo
  // a frame the backend has already run).
  journal_.clear();
  w_ = std::move(*next);
  std::swap(last_events_, events);
  events.clear();  // the frame before last's events: only their buffers are kept
  const std::uint64_t done = frame_++;
  const FrameRecord record{done, static_cast<double>(done) * options_.dt, last_events_, w_};
  struct Observing {
    const Engine* before;
    explicit Observing(const Engine* e) : before(observed) { observed = e; }
    ~Observing() { observed = before; }
  } observing(this);
  for (const auto& observer : observers_) observer(record);
  return true;
}

StopReason Engine::run(std::uint64_t max_frames) {
  const Use use(*this, "run");
  for (std::uint64_t k = 0; k < max_frames; ++k) {
    if (k > 0) fair_to_readers();
    const auto state = lock_state();
    if (w_.empty()) return StopReason::Empty;
    collect_events_unlocked(next_events_);
    run_frame(next_events_);
    if (stop_requested_) {
      stop_requested_ = false;
      return StopReason::Requested;
    }
    if (stop_when_ && stop_when_->done(w_, frame() - 1)) return StopReason::Done;
  }
  const auto state = lock_state();
  return w_.empty() ? StopReason::Empty : StopReason::FrameLimit;
}

}  // namespace vwg
