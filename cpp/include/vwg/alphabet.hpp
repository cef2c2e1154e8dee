// The alphabet of a world (paper §II.A): primitives P, transformations T, actor types A with the
// event types H each responds to, and event types D with the visual subset V. Names are interned
// here once; strings and events refer to them by integer id.
#pragma once

#include <atomic>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "vwg/value.hpp"

namespace vwg {

class ActorBehavior;

using SymbolId = std::uint32_t;
using EventTypeId = std::uint32_t;

enum class SymbolKind : std::uint8_t { Primitive, Transformation, Actor };
std::string_view kind_name(SymbolKind kind);

/// A set of event types, as a bitset over event type ids.
class EventSet {
 public:
  void insert(EventTypeId id);
  bool contains(EventTypeId id) const {
    const std::size_t word = id / 64;
    return word < bits_.size() && (bits_[word] >> (id % 64)) & 1U;
  }
  bool empty() const;

 private:
  std::vector<std::uint64_t> bits_;
};

struct SymbolInfo {
  SymbolId id = 0;
  std::string name;
  SymbolKind kind = SymbolKind::Primitive;
  /// Parameters (P, T) or attributes (A).
  Schema schema;
  /// Actors only: the event types H the actor responds to, in declaration order and as a set.
  std::vector<EventTypeId> responds_to;
  EventSet responds;
  /// Actors only: λ and θ. Null means an actor that never changes and never shows.
  std::shared_ptr<ActorBehavior> behavior;
  /// Actors only: index of the integer attribute called "id", or -1. Events addressed to an actor
  /// (Event::target) reach only actors whose id equals the target.
  int id_attribute = -1;
};

struct EventTypeInfo {
  EventTypeId id = 0;
  std::string name;
  bool visual = false;  ///< in V ⊆ D: seen by θ through π
  Schema fields;
};

/// Registry of the world's names. Append-only: ids never change once given. A name is used once
/// across symbols and event types; a second registration of a name is refused.
class Alphabet {
 public:
  SymbolId add_primitive(std::string name, Schema params = Schema::any());
  SymbolId add_transformation(std::string name, Schema params = Schema::any());
  EventTypeId add_event_type(std::string name, bool visual, Schema fields = {});
  /// `responds_to` names event types already registered (H ⊆ D).
  SymbolId add_actor(std::string name, const std::vector<std::string>& responds_to, Schema attributes,
                     std::shared_ptr<ActorBehavior> behavior);

  std::optional<SymbolId> find_symbol(std::string_view name) const;
  std::optional<EventTypeId> find_event_type(std::string_view name) const;
  /// Lookups that throw SchemaError with the expected kind named when the name is missing.
  SymbolId symbol_id(std::string_view name, std::optional<SymbolKind> expected = std::nullopt) const;
  EventTypeId event_type_id(std::string_view name) const;

  const SymbolInfo& symbol(SymbolId id) const { return symbols_[id]; }
  const EventTypeInfo& event_type(EventTypeId id) const { return events_[id]; }
  std::size_t symbol_count() const { return symbols_.size(); }
  std::size_t event_type_count() const { return events_.size(); }
  const std::vector<SymbolInfo>& symbols() const { return symbols_; }
  const std::vector<EventTypeInfo>& event_types() const { return events_; }

  /// Replace the behavior of an actor type (used by bindings that create the type first).
  void set_behavior(SymbolId actor, std::shared_ptr<ActorBehavior> behavior);

  /// True for names of the form [A-Za-z_][A-Za-z0-9_]* that are not reserved words.
  static bool valid_name(std::string_view name);

  /// Frames in progress that read this alphabet (engines hold a FrameUse while they run one):
  /// adding a name then would move the tables under their feet, so it is refused.
  class FrameUse {
   public:
    explicit FrameUse(const Alphabet& a) : a_(a) { ++a_.frames_in_progress_; }
    ~FrameUse() { --a_.frames_in_progress_; }
    FrameUse(const FrameUse&) = delete;
    FrameUse& operator=(const FrameUse&) = delete;

   private:
    const Alphabet& a_;
  };

 private:
  void check_not_in_use(const std::string& name) const;
  void claim_name(const std::string& name, bool is_event, std::uint32_t id);
  SymbolId add_symbol(std::string name, SymbolKind kind, Schema schema);

  struct Entry {
    bool is_event;
    std::uint32_t id;
  };
  struct StringHash {
    using is_transparent = void;
    std::size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
  };
  std::vector<SymbolInfo> symbols_;
  std::vector<EventTypeInfo> events_;
  std::unordered_map<std::string, Entry, StringHash, std::equal_to<>> names_;
  mutable std::atomic<int> frames_in_progress_{0};
};

/// Throws SchemaError unless event type `id` declares exactly these fields, with these kinds, in
/// this order (a generator that emits the type checks it once, when it is made).
void require_fields(const Alphabet& alphabet, EventTypeId id,
                    std::initializer_list<std::pair<const char*, ValueKind>> fields);

}  // namespace vwg
