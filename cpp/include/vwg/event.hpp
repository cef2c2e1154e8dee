// Events e^d_c (paper §II.C): an event type d with data c, optionally addressed to one actor.
// A frame's events S are one EventList, in generator priority order. The list stores its events
// in batches, one per emit: a sensor's scan (one event a beam, all to one robot) is one batch of
// real fields stored by columns (its distances side by side, then its angles): about 20 bytes a
// beam (two doubles and its batch's number) rather than a record and a tagged value per field.
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
  /// Field i (a copy: a batch stored by columns holds bare reals, not Values).
  Value value(std::size_t i) const;
  Datum datum(std::size_t i) const;
  double number(std::size_t i) const;
  const ValueStore& store() const;
  std::size_t index() const { return index_; }
  const EventList& list() const { return *list_; }

 private:
  const EventList* list_;
  std::size_t index_;
  std::uint32_t batch_;
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
  /// A batch of events of one type and target whose fields are all reals, given by columns:
  /// columns[k][j] is field k of event j (a laser's distances, then its angles). The same events
  /// as emit() of each in turn, checked as emit() checks them; a refused batch leaves the list as
  /// it was. Every column has one value per event.
  void emit_columns(EventTypeId type, std::span<const std::span<const double>> columns, std::int64_t target = kNoTarget);
  /// Append every event of another list of the same alphabet, in order (no re-check).
  void append(const EventList& other);
  /// Append event `i` of another list (no re-check).
  void append_from(const EventList& other, std::size_t i);

  std::size_t size() const { return batch_of_.size(); }
  bool empty() const { return batch_of_.empty(); }
  /// What a list holds, counted as its storage counts it: reserve() the sum of some lists' sizes
  /// and appending them all copies nothing.
  struct Sizes {
    std::size_t events = 0, batches = 0, values = 0, reals = 0;
    Sizes& operator+=(const Sizes& o) {
      events += o.events, batches += o.batches, values += o.values, reals += o.reals;
      return *this;
    }
  };
  Sizes sizes() const { return {batch_of_.size(), batches_.size(), store_.size(), reals_.size()}; }
  void reserve(const Sizes& room) {
    batch_of_.reserve(room.events);
    batches_.reserve(room.batches);
    store_.reserve(room.values, 0);
    reals_.reserve(room.reals);
  }
  /// A run of consecutive events of one type and target, as one emit made them.
  struct Batch {
    EventTypeId type;
    std::uint32_t first_event;  // the position of its first event in the list
    std::uint32_t count;        // its events
    std::uint32_t first;        // its first value: in reals_ if by_columns, else in store_
    std::int64_t target;
    std::uint32_t fields;  // each event's (those of its type)
    bool by_columns;       // field k of event j is reals_[first + k * count + j]; else store_[first + j * fields + k]
  };
  std::size_t batch_count() const { return batches_.size(); }
  const Batch& batch(std::size_t b) const { return batches_[b]; }
  EventView operator[](std::size_t i) const { return EventView(*this, i); }
  const Alphabet& alphabet() const { return *alphabet_; }
  const std::shared_ptr<const Alphabet>& alphabet_ptr() const { return alphabet_; }
  void clear() {
    batch_of_.clear();
    batches_.clear();
    store_.clear();
    reals_.clear();
    touch();
  }
  bool operator==(const EventList& other) const;
  /// A number no other list content has had in this process: it changes when the list does, so
  /// caches of converted events can tell lists apart even at a reused address.
  std::uint64_t serial() const { return serial_; }

 private:
  friend class EventView;
  std::shared_ptr<const Alphabet> alphabet_;
  std::vector<std::uint32_t> batch_of_;  // each event's batch
  std::vector<Batch> batches_;
  ValueStore store_;           // the fields of batches made by emit()
  std::vector<double> reals_;  // the columns of batches made by emit_columns()
  std::uint64_t serial_;
  void touch();
  void add_batch(EventTypeId type, std::uint32_t count, std::uint32_t first, std::int64_t target, std::uint32_t fields, bool by_columns);
};

/// Canonical text of one event, e.g. `eLaser<dist=1.5, angle=0.25>`; a target is printed first as
/// `to=3`.
std::string to_text(const EventView& e);

}  // namespace vwg
