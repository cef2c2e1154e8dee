// Events e^d_c (paper §II.C): an event type d with data c, optionally addressed to one actor.
// A frame's events S are one EventList, in generator priority order.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "vwg/alphabet.hpp"
#include "vwg/value.hpp"

namespace vwg {

/// No target: the event reaches every actor that responds to its type (the paper's broadcast).
inline constexpr std::int64_t kNoTarget = std::numeric_limits<std::int64_t>::min();

class EventList;

class EventView {
 public:
  EventView(const EventList& list, std::size_t index);
  EventTypeId type() const;
  const EventTypeInfo& info() const;
  /// The `id` of the actor this event is addressed to, or kNoTarget.
  std::int64_t target() const;
  bool has_target() const { return target() != kNoTarget; }
  std::size_t field_count() const;
  const Value& value(std::size_t i) const;
  Datum datum(std::size_t i) const;
  double number(std::size_t i) const;
  const ValueStore& store() const;
  std::size_t index() const { return index_; }
  const EventList& list() const { return *list_; }

 private:
  const EventList* list_;
  std::size_t index_;
};

class EventList {
 public:
  explicit EventList(std::shared_ptr<const Alphabet> alphabet);
  EventList(const EventList& other);
  EventList& operator=(const EventList& other);
  EventList(EventList&&) noexcept = default;
  EventList& operator=(EventList&&) noexcept = default;

  /// Append an event; fields are checked against the event type's schema.
  void emit(EventTypeId type, std::span<const Datum> fields = {}, std::int64_t target = kNoTarget);
  void emit(std::string_view type, std::initializer_list<Datum> fields = {},
            std::int64_t target = kNoTarget);
  /// emit() for an event whose fields are all reals, given in order, without a Datum for each (a
  /// sensor emits one event a beam). Checked as emit() checks them.
  void emit_reals(EventTypeId type, std::span<const double> fields, std::int64_t target = kNoTarget);
  /// Append every event of another list of the same alphabet, in order (no re-check).
  void append(const EventList& other);
  /// Append event `i` of another list (no re-check).
  void append_from(const EventList& other, std::size_t i);

  std::size_t size() const { return events_.size(); }
  /// The fields of all events together.
  std::size_t value_count() const { return store_.size(); }
  /// Room for `events` events with `values` fields in all, so appending that many copies nothing.
  void reserve(std::size_t events, std::size_t values) {
    events_.reserve(events);
    store_.reserve(values, 0);
  }
  bool empty() const { return events_.empty(); }
  EventView operator[](std::size_t i) const { return EventView(*this, i); }
  const Alphabet& alphabet() const { return *alphabet_; }
  const std::shared_ptr<const Alphabet>& alphabet_ptr() const { return alphabet_; }
  void clear() {
    events_.clear();
    store_.clear();
    touch();
  }
  bool operator==(const EventList& other) const;
  /// A number no other list content has had in this process: it changes when the list does, so
  /// caches of converted events can tell lists apart even at a reused address.
  std::uint64_t serial() const { return serial_; }

 private:
  friend class EventView;
  struct Record {
    EventTypeId type;
    std::uint32_t first_value;
    std::uint32_t value_count;
    std::int64_t target;
  };
  std::shared_ptr<const Alphabet> alphabet_;
  std::vector<Record> events_;
  ValueStore store_;
  std::uint64_t serial_;
  void touch();
};

/// Canonical text of one event, e.g. `eLaser<dist=1.5, angle=0.25>`; a target is printed first as
/// `to=3`.
std::string to_text(const EventView& e);

}  // namespace vwg
