#include "vwg/alphabet.hpp"

#include <string>

#include "vwg/actor.hpp"
#include "vwg/error.hpp"

namespace vwg {

std::string_view kind_name(SymbolKind kind) {
  switch (kind) {
    case SymbolKind::Primitive: return "primitive";
    case SymbolKind::Transformation: return "transformation";
    case SymbolKind::Actor: return "actor";
  }
  return "?";
}

void EventSet::insert(EventTypeId id) {
  const std::size_t word = id / 64;
  if (word >= bits_.size()) bits_.resize(word + 1, 0);
  bits_[word] |= std::uint64_t{1} << (id % 64);
}

bool EventSet::empty() const {
  for (auto w : bits_) {
    if (w) return false;
  }
  return true;
}

bool Alphabet::valid_name(std::string_view name) {
  if (name.empty() || name == "true" || name == "false") return false;
  auto alpha = [](char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_'; };
  if (!alpha(name[0])) return false;
  for (char c : name) {
    if (!alpha(c) && !(c >= '0' && c <= '9')) return false;
  }
  return true;
}

namespace {
void check_schema(const std::string& owner, Schema& schema, bool is_event) {
  for (std::size_t i = 0; i < schema.params.size(); ++i) {
    ParamSpec& p = schema.params[i];
    if (!Alphabet::valid_name(p.name)) {
      throw SchemaError(owner, "'" + p.name + "' is not a valid parameter name");
    }
    if (is_event && p.name == "to") {
      throw SchemaError(owner, "'to' is reserved for an event's target actor");
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (schema.params[j].name == p.name) {
        throw SchemaError(owner, "parameter '" + p.name + "' is declared twice");
      }
    }
    if (p.default_value) {
      // Validates the default's kind and finiteness; the widened value is kept.
      p.default_value = coerce(p, *p.default_value, owner);
    }
  }
}
}  // namespace

void Alphabet::claim_name(const std::string& name, bool is_event, std::uint32_t id) {
  if (!valid_name(name)) {
    throw SchemaError(name, "not a valid name: use letters, digits and '_', not starting with a "
                            "digit, and not 'true' or 'false'");
  }
  auto [it, inserted] = names_.emplace(name, Entry{is_event, id});
  if (!inserted) {
    const std::string what = it->second.is_event
                                 ? std::string("an event type")
                                 : "a " + std::string(kind_name(symbols_[it->second.id].kind));
    throw SchemaError(name, "the name is already registered as " + what);
  }
}

void Alphabet::check_not_in_use(const std::string& name) const {
  if (frames_in_progress_.load() > 0) {
    throw Error("Alphabet: cannot add '" + name + "' while an engine runs a frame with this alphabet "
                "(add names before running, not from a λ, θ, generator, backend or observer)");
  }
}

SymbolId Alphabet::add_symbol(std::string name, SymbolKind kind, Schema schema) {
  check_not_in_use(name);
  check_schema(name, schema, false);
  const auto id = static_cast<SymbolId>(symbols_.size());
  claim_name(name, false, id);
  SymbolInfo info;
  info.id = id;
  info.name = std::move(name);
  info.kind = kind;
  info.schema = std::move(schema);
  symbols_.push_back(std::move(info));
  return id;
}

SymbolId Alphabet::add_primitive(std::string name, Schema params) {
  return add_symbol(std::move(name), SymbolKind::Primitive, std::move(params));
}

SymbolId Alphabet::add_transformation(std::string name, Schema params) {
  return add_symbol(std::move(name), SymbolKind::Transformation, std::move(params));
}

EventTypeId Alphabet::add_event_type(std::string name, bool visual, Schema fields) {
  check_not_in_use(name);
  if (fields.variadic) throw SchemaError(name, "event fields must be declared by name");
  check_schema(name, fields, true);
  const auto id = static_cast<EventTypeId>(events_.size());
  claim_name(name, true, id);
  EventTypeInfo info;
  info.id = id;
  info.name = std::move(name);
  info.visual = visual;
  info.fields = std::move(fields);
  events_.push_back(std::move(info));
  return id;
}

SymbolId Alphabet::add_actor(std::string name, const std::vector<std::string>& responds_to,
                             Schema attributes, std::shared_ptr<ActorBehavior> behavior) {
  if (attributes.variadic) throw SchemaError(name, "actor attributes must be declared by name");
  std::vector<EventTypeId> events;
  for (const auto& e : responds_to) {
    auto id = find_event_type(e);
    if (!id) {
      throw SchemaError(name, "responds to '" + e + "', which is not a registered event type");
    }
    events.push_back(*id);
  }
  const SymbolId id = add_symbol(std::move(name), SymbolKind::Actor, std::move(attributes));
  SymbolInfo& info = symbols_[id];
  info.responds_to = events;
  for (auto e : events) info.responds.insert(e);
  info.behavior = std::move(behavior);
  const int id_attr = info.schema.index_of("id");
  if (id_attr >= 0 && info.schema.params[id_attr].kind == ValueKind::Int) info.id_attribute = id_attr;
  return id;
}

void Alphabet::set_behavior(SymbolId actor, std::shared_ptr<ActorBehavior> behavior) {
  check_not_in_use(actor < symbols_.size() ? symbols_[actor].name : std::to_string(actor));
  if (actor >= symbols_.size() || symbols_[actor].kind != SymbolKind::Actor) {
    throw SchemaError("set_behavior", "not an actor type");
  }
  symbols_[actor].behavior = std::move(behavior);
}

std::optional<SymbolId> Alphabet::find_symbol(std::string_view name) const {
  auto it = names_.find(name);
  if (it == names_.end() || it->second.is_event) return std::nullopt;
  return it->second.id;
}

std::optional<EventTypeId> Alphabet::find_event_type(std::string_view name) const {
  auto it = names_.find(name);
  if (it == names_.end() || !it->second.is_event) return std::nullopt;
  return it->second.id;
}

SymbolId Alphabet::symbol_id(std::string_view name, std::optional<SymbolKind> expected) const {
  auto id = find_symbol(name);
  const std::string what = expected ? std::string(kind_name(*expected)) : "symbol";
  if (!id) throw SchemaError(std::string(name), "unknown " + what + " (not in the alphabet)");
  if (expected && symbols_[*id].kind != *expected) {
    throw SchemaError(std::string(name), "is a " + std::string(kind_name(symbols_[*id].kind)) +
                                             ", expected a " + what);
  }
  return *id;
}

EventTypeId Alphabet::event_type_id(std::string_view name) const {
  auto id = find_event_type(name);
  if (!id) throw SchemaError(std::string(name), "unknown event type (not in the alphabet)");
  return *id;
}

void require_fields(const Alphabet& alphabet, EventTypeId id,
                    std::initializer_list<std::pair<const char*, ValueKind>> fields) {
  const EventTypeInfo& info = alphabet.event_type(id);
  std::string expected;
  for (const auto& [name, kind] : fields) {
    expected += (expected.empty() ? "" : ", ") + std::string(name) + ": " + std::string(kind_name(kind));
  }
  bool ok = info.fields.params.size() == fields.size();
  std::size_t i = 0;
  for (const auto& [name, kind] : fields) {
    ok = ok && info.fields.params[i].name == name && info.fields.params[i].kind == kind;
    ++i;
  }
  if (!ok) throw SchemaError(info.name, "expected the fields (" + expected + ")");
}

}  // namespace vwg
