// Actors (paper §II.B.3): λ rewrites an actor for an event it responds to (eq. 4), θ shows it as a
// string with no actors for a visual event (eq. 6). An ActorBehavior implements both for one type.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "vwg/alphabet.hpp"
#include "vwg/state.hpp"
#include "vwg/blob_edit.hpp"
#include "vwg/event.hpp"
#include "vwg/value.hpp"
#include "vwg/world_string.hpp"

namespace vwg {

/// One actor a<attr> being evolved or shown: its type and attribute values, readable and (for λ)
/// writable in place. Attribute i is the i-th of the type's schema.
class ActorState {
 public:
  ActorState() = default;
  /// Load the actor at node `index` of `s`.
  void load(const WorldString& s, std::size_t index);
  /// Load it from the engine's own string during a frame: edit_blob may then write in place into
  /// the blobs that only that string and this state hold, each change recorded in `journal`.
  void load_in_place(const WorldString& s, std::size_t index, BlobJournal& journal);
  /// A fresh actor of type `id` with the given attributes (checked against the schema).
  void assign(const Alphabet& alphabet, SymbolId id, std::span<const Datum> attributes);

  SymbolId symbol() const { return symbol_; }
  const SymbolInfo& info() const { return *info_; }
  std::size_t size() const { return store_.size(); }
  /// Index of the attribute `name`; throws SchemaError if the type has none.
  std::size_t index_of(std::string_view name) const;

  const Value& value(std::size_t i) const { return store_[static_cast<std::uint32_t>(i)]; }
  Datum get(std::size_t i) const;
  std::int64_t get_int(std::size_t i) const;
  double get_real(std::size_t i) const;
  double get_number(std::size_t i) const;  ///< Int or Real as double
  bool get_bool(std::size_t i) const;
  std::string_view get_text(std::size_t i) const;
  const std::shared_ptr<const Blob>& get_blob(std::size_t i) const;
  /// The actor's `id` attribute, if its type has one.
  std::optional<std::int64_t> id() const;

  void set(std::size_t i, const Datum& d);  ///< checked against the schema
  void set_int(std::size_t i, std::int64_t v);
  void set_real(std::size_t i, double v);  ///< throws SchemaError for NaN or infinity
  void set_bool(std::size_t i, bool v);
  void set_text(std::size_t i, std::string_view v);
  void set_blob(std::size_t i, std::shared_ptr<const Blob> v);
  /// Write access to a blob attribute: copied first if anyone else holds it (copy-on-write).
  Blob& mutable_blob(std::size_t i);
  /// Element writes to a blob attribute of element type T: in place when nobody but this state
  /// (and, in the engine's frame, the string it came from) can see it; else on a private copy.
  /// Cheaper than mutable_blob when a few elements of a large array change.
  template <class T>
  BlobEdit<T> edit_blob(std::size_t i) {
    BlobJournal* journal = nullptr;
    Blob& blob = writable_blob(i, dtype_of<T>(), journal);
    return BlobEdit<T>(blob, journal);
  }

  const ValueStore& store() const { return store_; }

 private:
  void expect(std::size_t i, ValueKind kind) const;
  Blob& writable_blob(std::size_t i, DType dtype, BlobJournal*& journal);
  template <class T>
  static constexpr DType dtype_of() {
    if constexpr (std::is_same_v<T, std::int8_t>) return DType::Int8;
    else if constexpr (std::is_same_v<T, std::uint8_t>) return DType::UInt8;
    else if constexpr (std::is_same_v<T, std::int16_t>) return DType::Int16;
    else if constexpr (std::is_same_v<T, std::int32_t>) return DType::Int32;
    else if constexpr (std::is_same_v<T, std::int64_t>) return DType::Int64;
    else if constexpr (std::is_same_v<T, float>) return DType::Float32;
    else {
      static_assert(std::is_same_v<T, double>, "a blob element is an int8..int64, float or double");
      return DType::Float64;
    }
  }
  SymbolId symbol_ = 0;
  const SymbolInfo* info_ = nullptr;
  ValueStore store_;  // attribute i is store_[i]; replaced text and blobs leave garbage until load
  // Set by load_in_place: the journal, and the blobs as loaded (the ones the string also holds).
  BlobJournal* journal_ = nullptr;
  std::vector<const Blob*> loaded_blobs_;
};

/// Canonical text of the actor, e.g. `ARobot<id=1, row=3, ...>`.
std::string to_text(const ActorState& actor);

/// What λ and θ know about the frame. `seed` is unique to (engine seed, frame, actor position,
/// event position), so a random decision is reproducible.
struct EvolutionContext {
  std::uint64_t frame = 0;
  double time = 0.0;
  std::uint64_t seed = 0;
};

/// The result of one λ call. By default the actor stays one actor (its state, maybe changed in
/// place). A behavior that returns any other string — ε, several symbols, the actor inside
/// transformations — calls replace() and builds it.
class Replacement {
 public:
  explicit Replacement(std::shared_ptr<const Alphabet> alphabet) : builder_(std::move(alphabet)) {}
  /// Start (or continue) building the replacement string; include the actor with builder.actor(state).
  StringBuilder& replace() {
    replaced_ = true;
    return builder_;
  }
  /// Replace by a ready-made string.
  void replace_with(const WorldString& s) { replace().append(s); }
  bool replaced() const { return replaced_; }
  WorldString finish() {
    replaced_ = false;
    return builder_.finish();
  }

 private:
  StringBuilder builder_;
  bool replaced_ = false;
};

/// Numeric and boolean attribute columns of many actors of one type, for batch λ. Column j holds
/// attribute j for every actor; text and blob attributes have empty columns (read-only in batch).
struct ActorBatch {
  SymbolId symbol = 0;
  std::size_t count = 0;
  std::vector<std::shared_ptr<std::vector<std::int64_t>>> ints;   // per attribute, or null
  std::vector<std::shared_ptr<std::vector<double>>> reals;        // per attribute, or null
  std::vector<std::shared_ptr<std::vector<std::uint8_t>>> bools;  // per attribute, or null
};

/// λ and θ of one actor type. Subclass in C++, or define an actor class in Python.
class ActorBehavior {
 public:
  virtual ~ActorBehavior() = default;

  /// λ(a, e) for an event whose type is in H (others never reach it; the actor stays unchanged,
  /// eq. 4 last case). Change `self` in place, or build another string through `out`.
  virtual void evolve(ActorState& self, const EventView& e, const EvolutionContext& ctx,
                      Replacement& out) = 0;

  /// θ(a, e) for a visual event in H ∩ V: append a string with no actors to `out`. Appending
  /// nothing is ε (eq. 6). The default shows nothing.
  virtual void visualize(const ActorState& self, const EventView& e, const EvolutionContext& ctx,
                         StringBuilder& out) {
    (void)self, (void)e, (void)ctx, (void)out;
  }

  /// True if λ runs over all actors of the type at once through evolve_batch. A batch behavior
  /// keeps every actor a single actor of its type and changes only Int, Real and Bool attributes.
  virtual bool batched() const { return false; }
  /// True if λ may run for several actors of this behaviour at the same time, on the engine's
  /// threads: λ then touches only its own actor's state and what it alone owns (or guards). The
  /// engine's result is the same as one thread's. The default, false, runs λ on the engine's
  /// thread in string order (a Python actor's, say).
  virtual bool concurrent() const { return false; }
  /// Batch λ for one event over the actors in `batch` (those that receive it), in string order.
  virtual void evolve_batch(ActorBatch& batch, const EventView& e, const EvolutionContext& ctx) {
    (void)batch, (void)e, (void)ctx;
  }

  /// True if λ takes the events of type `type` a run at a time, through evolve_run.
  virtual bool takes_runs(EventTypeId type) const {
    (void)type;
    return false;
  }
  /// λ folded over a run of events of one type that all reach this actor, in S order (positions
  /// `at` of `events`, with no other event for the actor between them): the same as evolve() on
  /// each in turn (DESIGN.md choice 1), done at once — a robot's laser scan, one beam an event, is
  /// one edit of its map. It keeps the actor one actor of its type with the same id. `ctx` is that
  /// of the run's first event. The default calls evolve() on each.
  virtual void evolve_run(ActorState& self, const EventList& events, std::span<const std::uint32_t> at,
                          const EvolutionContext& ctx, Replacement& out) {
    for (const std::uint32_t i : at) evolve(self, events[i], ctx, out);
  }

  /// What λ keeps outside the string that decides anything (a decider's searches), for a saved run
  /// (vwg/state.hpp). The paper's actor keeps its state in its attributes, in the string: the
  /// default keeps nothing. A cache that only repeats what the string holds is not kept.
  virtual void save_state(StateWriter& out) const { (void)out; }
  /// Back to what save_state() wrote (before the first frame of a resumed run).
  virtual void load_state(StateReader& in) { in.end(); }
};

}  // namespace vwg
