#include "vwg/actor.hpp"

#include <cmath>
#include <string>

#include "vwg/error.hpp"

namespace vwg {

void ActorState::load(const WorldString& s, std::size_t index) {
  const Node& n = s.nodes()[index];
  symbol_ = n.symbol;
  info_ = &s.alphabet().symbol(n.symbol);
  store_.clear();
  store_.push_range(s.store(), n.first_value, n.value_count);
  journal_ = nullptr;
}

void ActorState::load_in_place(const WorldString& s, std::size_t index, BlobJournal& journal) {
  load(s, index);
  journal_ = &journal;
  loaded_blobs_.assign(size(), nullptr);
  for (std::size_t k = 0; k < size(); ++k) {
    if (value(k).kind == ValueKind::Blob) loaded_blobs_[k] = store_.blob(value(k)).get();
  }
}

void ActorState::assign(const Alphabet& alphabet, SymbolId id, std::span<const Datum> attributes) {
  const SymbolInfo& info = alphabet.symbol(id);
  if (info.kind != SymbolKind::Actor) throw SchemaError(info.name, "is not an actor type");
  const auto checked = StringBuilder::check_params(info, attributes);
  symbol_ = id;
  info_ = &info;
  store_.clear();
  for (const Datum& d : checked) store_.push(d);
  journal_ = nullptr;
}

std::size_t ActorState::index_of(std::string_view name) const {
  const int i = info_->schema.index_of(name);
  if (i < 0) throw SchemaError(info_->name + "." + std::string(name), "no such attribute");
  return static_cast<std::size_t>(i);
}

void ActorState::expect(std::size_t i, ValueKind kind) const {
  if (i >= size()) {
    throw SchemaError(info_->name, "attribute index " + std::to_string(i) + " out of range");
  }
  const ValueKind have = info_->schema.params[i].kind;
  if (have != kind) {
    throw SchemaError(info_->name + "." + info_->schema.params[i].name,
                      "is " + std::string(kind_name(have)) + ", not " + std::string(kind_name(kind)));
  }
}

Datum ActorState::get(std::size_t i) const { return store_.datum(value(i)); }
std::int64_t ActorState::get_int(std::size_t i) const {
  expect(i, ValueKind::Int);
  return value(i).i;
}
double ActorState::get_real(std::size_t i) const {
  expect(i, ValueKind::Real);
  return value(i).r;
}
double ActorState::get_number(std::size_t i) const {
  const Value& v = value(i);
  if (v.kind == ValueKind::Int) return static_cast<double>(v.i);
  expect(i, ValueKind::Real);
  return v.r;
}
bool ActorState::get_bool(std::size_t i) const {
  expect(i, ValueKind::Bool);
  return value(i).b;
}
std::string_view ActorState::get_text(std::size_t i) const {
  expect(i, ValueKind::Text);
  return store_.text(value(i));
}
const std::shared_ptr<const Blob>& ActorState::get_blob(std::size_t i) const {
  expect(i, ValueKind::Blob);
  return store_.blob(value(i));
}

std::optional<std::int64_t> ActorState::id() const {
  if (info_->id_attribute < 0) return std::nullopt;
  return value(static_cast<std::size_t>(info_->id_attribute)).i;
}

void ActorState::set(std::size_t i, const Datum& d) {
  if (i >= size()) throw SchemaError(info_->name, "attribute index out of range");
  store_.set(static_cast<std::uint32_t>(i), coerce(info_->schema.params[i], d, info_->name));
}
void ActorState::set_int(std::size_t i, std::int64_t v) {
  expect(i, ValueKind::Int);
  store_[static_cast<std::uint32_t>(i)].i = v;
}
void ActorState::set_real(std::size_t i, double v) {
  expect(i, ValueKind::Real);
  if (!std::isfinite(v)) {
    throw SchemaError(info_->name + "." + info_->schema.params[i].name,
                      "expected a finite real, got " + std::to_string(v));
  }
  store_[static_cast<std::uint32_t>(i)].r = v;
}
void ActorState::set_bool(std::size_t i, bool v) {
  expect(i, ValueKind::Bool);
  store_[static_cast<std::uint32_t>(i)].b = v;
}
void ActorState::set_text(std::size_t i, std::string_view v) {
  expect(i, ValueKind::Text);
  store_.set(static_cast<std::uint32_t>(i), Datum(v));
}
void ActorState::set_blob(std::size_t i, std::shared_ptr<const Blob> v) {
  expect(i, ValueKind::Blob);
  if (!v) throw SchemaError(info_->name + "." + info_->schema.params[i].name, "null blob");
  store_.set(static_cast<std::uint32_t>(i), Datum(std::move(v)));
}

Blob& ActorState::writable_blob(std::size_t i, DType dtype, BlobJournal*& journal) {
  expect(i, ValueKind::Blob);
  const std::shared_ptr<const Blob>& held = store_.blob(value(i));
  if (held->dtype() != dtype) {
    throw SchemaError(info_->name + "." + info_->schema.params[i].name,
                      "holds " + std::string(dtype_name(held->dtype())) + " elements, edited as " +
                          std::string(dtype_name(dtype)));
  }
  // Every reference to a blob has a slot of its own (ValueStore), so the count sees another
  // attribute, another actor, a snapshot or Python holding it.
  journal = nullptr;
  // Held here alone (made in this frame): nobody can see the writes.
  if (held.use_count() == 1) return const_cast<Blob&>(*held);
  // Held here and by the engine's string it was loaded from, nowhere else (not by Python, a
  // snapshot, another actor or the display): written in place, each change journaled.
  if (journal_ && held.use_count() == 2 && i < loaded_blobs_.size() && loaded_blobs_[i] == held.get()) {
    journal = journal_;
    return const_cast<Blob&>(*held);
  }
  std::shared_ptr<Blob> copy = held->clone();
  Blob& ref = *copy;
  store_.set(static_cast<std::uint32_t>(i), Datum(std::shared_ptr<const Blob>(std::move(copy))));
  return ref;
}

Blob& ActorState::mutable_blob(std::size_t i) {
  expect(i, ValueKind::Blob);
  const std::shared_ptr<const Blob>& held = store_.blob(value(i));
  // Held only here, by this attribute alone: write in place. Shared with the string being read, a
  // snapshot, Python or another attribute: write to a private copy.
  if (held.use_count() == 1) return const_cast<Blob&>(*held);  // a slot per reference (ValueStore)
  std::shared_ptr<Blob> copy = held->clone();
  Blob& ref = *copy;
  store_.set(static_cast<std::uint32_t>(i), Datum(std::shared_ptr<const Blob>(std::move(copy))));
  return ref;
}

}  // namespace vwg
