#include "vwg/event.hpp"

#include <atomic>
#include <cmath>
#include <limits>
#include <string>

#include "src/unique_number.hpp"
#include "vwg/error.hpp"
#include "vwg/text.hpp"

namespace vwg {

EventView::EventView(const EventList& list, std::size_t index)
    : list_(&list), index_(index), batch_(list.batch_of_[index]) {}
EventTypeId EventView::type() const { return list_->batches_[batch_].type; }
const EventTypeInfo& EventView::info() const { return list_->alphabet().event_type(type()); }
std::int64_t EventView::target() const { return list_->batches_[batch_].target; }
std::size_t EventView::field_count() const { return list_->batches_[batch_].fields; }
Value EventView::value(std::size_t i) const {
  const EventList::Batch& b = list_->batches_[batch_];
  const std::size_t fields = b.fields;
  if (i >= fields) {
    throw SchemaError(info().name, "has " + std::to_string(fields) + " fields; no field " + std::to_string(i));
  }
  const std::size_t j = index_ - b.first_event;
  if (!b.by_columns) return list_->store_[static_cast<std::uint32_t>(b.first + j * fields + i)];
  Value v;
  v.kind = ValueKind::Real;
  v.r = list_->reals_[b.first + i * b.count + j];
  return v;
}
Datum EventView::datum(std::size_t i) const { return list_->store_.datum(value(i)); }
const ValueStore& EventView::store() const { return list_->store_; }

double EventView::number(std::size_t i) const {
  const Value v = value(i);
  if (v.kind == ValueKind::Int) return static_cast<double>(v.i);
  if (v.kind == ValueKind::Real) return v.r;
  throw SchemaError(info().name + "." + info().fields.params[i].name, "is not a number");
}

struct EventListSerials;

void EventList::touch() { serial_ = next_unique_number<EventListSerials>(); }

EventList::EventList(std::shared_ptr<const Alphabet> alphabet) : alphabet_(std::move(alphabet)) {
  if (!alphabet_) throw Error("an event list needs an alphabet");
  touch();
}

EventList::EventList(const EventList& other)
    : alphabet_(other.alphabet_),
      batch_of_(other.batch_of_),
      batches_(other.batches_),
      store_(other.store_),
      reals_(other.reals_),
      serial_(other.serial_) {}

EventList& EventList::operator=(const EventList& other) {
  alphabet_ = other.alphabet_;
  batch_of_ = other.batch_of_;
  batches_ = other.batches_;
  store_ = other.store_;
  reals_ = other.reals_;
  serial_ = other.serial_;  // same content, same serial
  return *this;
}

void EventList::add_batch(EventTypeId type, std::uint32_t count, std::uint32_t first, std::int64_t target, std::uint32_t fields,
                          bool by_columns) {
  const auto b = static_cast<std::uint32_t>(batches_.size());
  batches_.push_back(Batch{type, static_cast<std::uint32_t>(batch_of_.size()), count, first, target, fields, by_columns});
  batch_of_.insert(batch_of_.end(), count, b);
}

void EventList::emit(EventTypeId type, std::span<const Datum> fields, std::int64_t target) {
  if (type >= alphabet_->event_type_count()) throw SchemaError("event", "unknown event type id");
  const EventTypeInfo& info = alphabet_->event_type(type);
  const auto& specs = info.fields.params;
  if (fields.size() > specs.size()) {
    throw SchemaError(info.name, "has " + std::to_string(specs.size()) + " fields, got " +
                                     std::to_string(fields.size()));
  }
  // Check all fields before storing any, so a bad event leaves the list as it was (in a buffer
  // kept by the thread: a generator emits thousands of events a frame).
  thread_local std::vector<Datum> checked;
  checked.clear();
  struct Forget {  // holds no value (a blob would stay alive) once the call is over
    ~Forget() { checked.clear(); }
  } forget;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (i < fields.size()) {
      checked.push_back(coerce(specs[i], fields[i], info.name));
    } else if (specs[i].default_value) {
      checked.push_back(*specs[i].default_value);
    } else {
      throw SchemaError(info.name + "." + specs[i].name, "missing (it has no default)");
    }
  }
  const std::uint32_t first = store_.size();
  for (const Datum& d : checked) store_.push(d);
  add_batch(type, 1, first, target, static_cast<std::uint32_t>(specs.size()), false);
  touch();
}

void EventList::emit_columns(EventTypeId type, std::span<const std::span<const double>> columns, std::int64_t target) {
  if (type >= alphabet_->event_type_count()) throw SchemaError("event", "unknown event type id");
  const EventTypeInfo& info = alphabet_->event_type(type);
  const auto& specs = info.fields.params;
  if (columns.size() != specs.size()) {
    throw SchemaError(info.name, "has " + std::to_string(specs.size()) + " fields, got " + std::to_string(columns.size()) + " columns");
  }
  if (columns.empty()) throw SchemaError(info.name, "has no fields: emit its events one by one");
  const std::size_t count = columns[0].size();
  for (std::size_t k = 0; k < specs.size(); ++k) {
    if (specs[k].kind != ValueKind::Real) {
      throw SchemaError(info.name + "." + specs[k].name, "is not a real: only events whose fields are all reals come by columns");
    }
    if (columns[k].size() != count) {
      throw SchemaError(info.name + "." + specs[k].name, "has " + std::to_string(columns[k].size()) + " values; the column of " +
                                                             specs[0].name + " has " + std::to_string(count) +
                                                             " (one value an event in every column)");
    }
    for (const double x : columns[k]) {
      if (!std::isfinite(x)) (void)coerce(specs[k], Datum(x), info.name);  // refused as emit() refuses it
    }
  }
  if (count == 0) return;
  if (batch_of_.size() + count > std::numeric_limits<std::uint32_t>::max() ||
      reals_.size() + count * specs.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw Error("an event list holds at most 2^32 - 1 events and reals");
  }
  const auto first = static_cast<std::uint32_t>(reals_.size());
  for (const std::span<const double> column : columns) reals_.insert(reals_.end(), column.begin(), column.end());
  add_batch(type, static_cast<std::uint32_t>(count), first, target, static_cast<std::uint32_t>(specs.size()), true);
  touch();
}

void EventList::emit(std::string_view type, std::initializer_list<Datum> fields, std::int64_t target) {
  emit(alphabet_->event_type_id(type), {fields.begin(), fields.end()}, target);
}

void EventList::append(const EventList& other) {
  if (other.alphabet_ != alphabet_) throw Error("EventList.append: the events use another alphabet");
  batch_of_.reserve(batch_of_.size() + other.batch_of_.size());
  for (const Batch& b : other.batches_) {
    const auto n = b.count * b.fields;
    std::uint32_t first;
    if (b.by_columns) {
      first = static_cast<std::uint32_t>(reals_.size());
      reals_.insert(reals_.end(), other.reals_.begin() + b.first, other.reals_.begin() + b.first + n);
    } else {
      first = store_.push_range(other.store_, b.first, n);
    }
    add_batch(b.type, b.count, first, b.target, b.fields, b.by_columns);
  }
  touch();
}

void EventList::append_from(const EventList& other, std::size_t i) {
  const Batch& b = other.batches_[other.batch_of_[i]];
  const std::size_t fields = b.fields, j = i - b.first_event;
  std::uint32_t first;
  if (b.by_columns) {
    first = static_cast<std::uint32_t>(reals_.size());
    for (std::size_t k = 0; k < fields; ++k) reals_.push_back(other.reals_[b.first + k * b.count + j]);
  } else {
    first = store_.push_range(other.store_, static_cast<std::uint32_t>(b.first + j * fields), static_cast<std::uint32_t>(fields));
  }
  add_batch(b.type, 1, first, b.target, b.fields, b.by_columns);
  touch();
}

bool EventList::operator==(const EventList& other) const {
  if (size() != other.size()) return false;
  for (std::size_t i = 0; i < size(); ++i) {
    const EventView a = (*this)[i], b = other[i];
    if (a.type() != b.type() || a.target() != b.target() || a.field_count() != b.field_count()) return false;
    for (std::size_t k = 0; k < a.field_count(); ++k) {
      if (!ValueStore::equal(store_, a.value(k), other.store_, b.value(k))) return false;
    }
  }
  return true;
}

std::string to_text(const EventView& e) {
  const EventTypeInfo& info = e.info();
  std::string out = info.name;
  if (e.field_count() == 0 && !e.has_target()) return out;
  out += '<';
  bool first = true;
  if (e.has_target()) {
    out += "to=" + std::to_string(e.target());
    first = false;
  }
  for (std::size_t i = 0; i < e.field_count(); ++i) {
    if (!first) out += ", ";
    first = false;
    out += info.fields.params[i].name;
    out += '=';
    append_value_text(out, e.store(), e.value(i));
  }
  out += '>';
  return out;
}

}  // namespace vwg
