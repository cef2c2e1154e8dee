#include "vwg/event.hpp"

#include <atomic>
#include <cmath>
#include <string>

#include "vwg/error.hpp"
#include "vwg/text.hpp"
#include "vwg/unique_number.hpp"

namespace vwg {

EventView::EventView(const EventList& list, std::size_t index) : list_(&list), index_(index) {}
EventTypeId EventView::type() const { return list_->events_[index_].type; }
const EventTypeInfo& EventView::info() const { return list_->alphabet().event_type(type()); }
std::int64_t EventView::target() const { return list_->events_[index_].target; }
std::size_t EventView::field_count() const { return list_->events_[index_].value_count; }
const Value& EventView::value(std::size_t i) const {
  if (i >= field_count()) {
    throw SchemaError(info().name, "has " + std::to_string(field_count()) + " fields; no field " + std::to_string(i));
  }
  return list_->store_[list_->events_[index_].first_value + static_cast<std::uint32_t>(i)];
}
Datum EventView::datum(std::size_t i) const { return list_->store_.datum(value(i)); }
const ValueStore& EventView::store() const { return list_->store_; }

double EventView::number(std::size_t i) const {
  const Value& v = value(i);
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
    : alphabet_(other.alphabet_), events_(other.events_), store_(other.store_), serial_(other.serial_) {}

EventList& EventList::operator=(const EventList& other) {
  alphabet_ = other.alphabet_;
  events_ = other.events_;
  store_ = other.store_;
  serial_ = other.serial_;  // same content, same serial
  return *this;
}

void EventList::emit(EventTypeId type, std::span<const Datum> fields, std::int64_t target) {
  if (type >= alphabet_->event_type_count()) throw SchemaError("event", "unknown event type id");
  const EventTypeInfo& info = alphabet_->event_type(type);
  const auto& specs = info.fields.params;
  if (fields.size() > specs.size()) {
    throw SchemaError(info.name, "has " + std::to_string(specs.size()) + " fields, got " +
                                     std::to_string(fields.size()));
  }
  Record r{type, store_.size(), static_cast<std::uint32_t>(specs.size()), target};
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
  for (const Datum& d : checked) store_.push(d);
  events_.push_back(r);
  touch();
}

void EventList::emit_reals(EventTypeId type, std::span<const double> fields, std::int64_t target) {
  bool plain = type < alphabet_->event_type_count() && !fields.empty();
  if (plain) {
    const std::vector<ParamSpec>& specs = alphabet_->event_type(type).fields.params;
    plain = specs.size() == fields.size();
    for (std::size_t i = 0; plain && i < fields.size(); ++i) plain = specs[i].kind == ValueKind::Real && std::isfinite(fields[i]);
  }
  if (!plain) {  // what emit() refuses, it refuses with its own message
    std::vector<Datum> data(fields.begin(), fields.end());
    emit(type, data, target);
    return;
  }
  const Record r{type, store_.size(), static_cast<std::uint32_t>(fields.size()), target};
  for (const double x : fields) store_.push_real(x);
  events_.push_back(r);
  touch();
}

void EventList::emit(std::string_view type, std::initializer_list<Datum> fields, std::int64_t target) {
  emit(alphabet_->event_type_id(type), {fields.begin(), fields.end()}, target);
}

void EventList::append(const EventList& other) {
  if (other.alphabet_ != alphabet_) throw Error("EventList.append: the events use another alphabet");
  events_.reserve(events_.size() + other.events_.size());
  for (const Record& r : other.events_) {
    const std::uint32_t first = store_.push_range(other.store_, r.first_value, r.value_count);
    events_.push_back(Record{r.type, first, r.value_count, r.target});
  }
  touch();
}

void EventList::append_from(const EventList& other, std::size_t i) {
  const Record& r = other.events_[i];
  const std::uint32_t first = store_.push_range(other.store_, r.first_value, r.value_count);
  events_.push_back(Record{r.type, first, r.value_count, r.target});
  touch();
}

bool EventList::operator==(const EventList& other) const {
  if (events_.size() != other.events_.size()) return false;
  for (std::size_t i = 0; i < events_.size(); ++i) {
    const Record& a = events_[i];
    const Record& b = other.events_[i];
    if (a.type != b.type || a.target != b.target || a.value_count != b.value_count) return false;
    for (std::uint32_t k = 0; k < a.value_count; ++k) {
      if (!ValueStore::equal(store_, store_[a.first_value + k], other.store_, other.store_[b.first_value + k])) {
        return false;
      }
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
