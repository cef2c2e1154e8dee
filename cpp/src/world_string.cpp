#include "vwg/world_string.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "vwg/actor.hpp"
#include "vwg/error.hpp"
#include "vwg/hash.hpp"

namespace vwg {

NodeView::NodeView(const WorldString& s, std::size_t index)
    : s_(&s), node_(&s.nodes()[index]), index_(index) {}

const SymbolInfo& NodeView::info() const { return s_->alphabet().symbol(node_->symbol); }
const Value& NodeView::value(std::size_t i) const {
  if (i >= node_->value_count) {
    throw SchemaError(info().name, "has " + std::to_string(node_->value_count) + " parameters; no parameter " + std::to_string(i));
  }
  return s_->store()[node_->first_value + static_cast<std::uint32_t>(i)];
}
Datum NodeView::datum(std::size_t i) const { return s_->store().datum(value(i)); }
const ValueStore& NodeView::store() const { return s_->store(); }

double NodeView::number(std::size_t i) const {
  const Value& v = value(i);
  if (v.kind == ValueKind::Int) return static_cast<double>(v.i);
  if (v.kind == ValueKind::Real) return v.r;
  throw SchemaError(info().name + "[" + std::to_string(i) + "]",
                    "expected a number, got " + std::string(kind_name(v.kind)));
}

WorldString::WorldString(std::shared_ptr<const Alphabet> alphabet) : alphabet_(std::move(alphabet)) {
  if (!alphabet_) throw Error("a world string needs an alphabet");
}

bool WorldString::operator==(const WorldString& other) const {
  if (alphabet_ != other.alphabet_ || nodes_.size() != other.nodes_.size()) return false;
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Node& a = nodes_[i];
    const Node& b = other.nodes_[i];
    if (a.symbol != b.symbol || a.kind != b.kind || a.value_count != b.value_count || a.joined != b.joined) {
      return false;
    }
    if (a.kind == NodeKind::Close) continue;
    for (std::uint16_t k = 0; k < a.value_count; ++k) {
      if (!ValueStore::equal(store_, store_[a.first_value + k], other.store_,
                             other.store_[b.first_value + k])) {
        return false;
      }
    }
  }
  return true;
}

std::uint64_t WorldString::content_hash() const {
  std::uint64_t h = 0x776F726C64ULL;
  for (const Node& n : nodes_) {
    // A figure's later primitives mix a mark in; a string without figures hashes as it always did.
    if (n.joined) h = hash_combine(h, 0x6A6F696E6564ULL);  // "joined"
    const std::string& name = alphabet_->symbol(n.symbol).name;
    h = hash_bytes(name.data(), name.size(), hash_combine(h, static_cast<std::uint64_t>(n.kind)));
    if (n.kind == NodeKind::Close) continue;
    for (std::uint16_t k = 0; k < n.value_count; ++k) h = hash_combine(h, store_.hash(store_[n.first_value + k]));
  }
  return h;
}

// ---------------------------------------------------------------------------------------------

StringBuilder::StringBuilder(std::shared_ptr<const Alphabet> alphabet) : out_(std::move(alphabet)) {}

void StringBuilder::reserve(std::size_t nodes, std::size_t values, std::size_t chars) {
  out_.nodes_.reserve(nodes);
  out_.store_.reserve(values, chars);
}

std::vector<Datum> StringBuilder::check_params(const SymbolInfo& info, std::span<const Datum> params) {
  const Schema& schema = info.schema;
  if (schema.variadic) {
    for (const Datum& d : params) {
      if (d.kind() == ValueKind::Real && !std::isfinite(d.as_real())) {
        throw SchemaError(info.name, "parameters must be finite reals, got " + std::to_string(d.as_real()));
      }
      if (d.kind() == ValueKind::Blob && !d.as_blob()) throw SchemaError(info.name, "null blob");
    }
    return {params.begin(), params.end()};
  }
  if (params.size() > schema.params.size()) {
    throw SchemaError(info.name, "takes " + std::to_string(schema.params.size()) + " " +
                                     (info.kind == SymbolKind::Actor ? "attributes" : "parameters") +
                                     ", got " + std::to_string(params.size()));
  }
  std::vector<Datum> out;
  out.reserve(schema.params.size());
  for (std::size_t i = 0; i < schema.params.size(); ++i) {
    const ParamSpec& spec = schema.params[i];
    if (i < params.size()) {
      out.push_back(coerce(spec, params[i], info.name));
    } else if (spec.default_value) {
      out.push_back(*spec.default_value);
    } else {
      throw SchemaError(info.name + "." + spec.name, "missing (it has no default)");
    }
  }
  return out;
}

void StringBuilder::push_node(SymbolId id, NodeKind kind, std::span<const Datum> params, bool joined) {
  const SymbolInfo& info = out_.alphabet_->symbol(id);
  const auto checked = check_params(info, params);
  if (checked.size() > 0xFFFF) throw SchemaError(info.name, "more than 65535 parameters");
  Node n{id, out_.store_.size(), static_cast<std::uint16_t>(checked.size()), kind, joined};
  for (const Datum& d : checked) out_.store_.push(d);
  out_.nodes_.push_back(n);
  if (kind == NodeKind::Actor) ++out_.actor_count_;
}

namespace {
void expect_kind(const SymbolInfo& info, SymbolKind kind) {
  if (info.kind != kind) {
    throw SchemaError(info.name, "is a " + std::string(kind_name(info.kind)) + ", not a " +
                                     std::string(kind_name(kind)));
  }
}
}  // namespace

StringBuilder& StringBuilder::primitive(SymbolId id, std::span<const Datum> params) {
  expect_kind(out_.alphabet_->symbol(id), SymbolKind::Primitive);
  push_node(id, NodeKind::Primitive, params);
  return *this;
}

StringBuilder& StringBuilder::primitive(std::string_view name, std::initializer_list<Datum> params) {
  return primitive(out_.alphabet_->symbol_id(name, SymbolKind::Primitive), {params.begin(), params.end()});
}

bool StringBuilder::ends_with_primitive() const {
  return !out_.nodes_.empty() && out_.nodes_.back().kind == NodeKind::Primitive;
}

StringBuilder& StringBuilder::juxtapose(SymbolId id, std::span<const Datum> params) {
  const SymbolInfo& info = out_.alphabet_->symbol(id);
  expect_kind(info, SymbolKind::Primitive);
  if (!ends_with_primitive()) {
    throw SchemaError(info.name, "cannot be juxtaposed here: a figure (rule 6, FIGURE → p+) joins a primitive "
                                 "to the primitive just before it, and the string does not end with one");
  }
  push_node(id, NodeKind::Primitive, params, true);
  return *this;
}

StringBuilder& StringBuilder::juxtapose(std::string_view name, std::initializer_list<Datum> params) {
  return juxtapose(out_.alphabet_->symbol_id(name, SymbolKind::Primitive), {params.begin(), params.end()});
}

StringBuilder& StringBuilder::open(SymbolId id, std::span<const Datum> params) {
  expect_kind(out_.alphabet_->symbol(id), SymbolKind::Transformation);
  open_.push_back(out_.nodes_.size());
  push_node(id, NodeKind::Transformation, params);
  return *this;
}

StringBuilder& StringBuilder::open(std::string_view name, std::initializer_list<Datum> params) {
  return open(out_.alphabet_->symbol_id(name, SymbolKind::Transformation), {params.begin(), params.end()});
}

StringBuilder& StringBuilder::close() {
  if (open_.empty()) throw Error("close() without an open scope");
  const std::size_t t = open_.back();
  open_.pop_back();
  if (t + 1 == out_.nodes_.size()) {
    // Empty scope: drop the transformation and its values (t(ε) is not a word of L(M)).
    out_.store_.truncate(out_.nodes_[t].first_value);
    out_.nodes_.pop_back();
    return *this;
  }
  const Node& open_node = out_.nodes_[t];
  out_.nodes_.push_back(Node{open_node.symbol, open_node.first_value, open_node.value_count, NodeKind::Close, false});
  ++out_.close_count_;
  return *this;
}

StringBuilder& StringBuilder::actor(SymbolId id, std::span<const Datum> attributes) {
  expect_kind(out_.alphabet_->symbol(id), SymbolKind::Actor);
  push_node(id, NodeKind::Actor, attributes);
  return *this;
}

StringBuilder& StringBuilder::actor(std::string_view name, std::initializer_list<Datum> attributes) {
  return actor(out_.alphabet_->symbol_id(name, SymbolKind::Actor), {attributes.begin(), attributes.end()});
}

StringBuilder& StringBuilder::actor(const ActorState& state) {
  Node n{state.symbol(), out_.store_.size(), static_cast<std::uint16_t>(state.size()), NodeKind::Actor, false};
  for (std::size_t i = 0; i < state.size(); ++i) out_.store_.push_from(state.store(), state.value(i));
  out_.nodes_.push_back(n);
  ++out_.actor_count_;
  return *this;
}

StringBuilder& StringBuilder::append(const WorldString& s) { return append_range(s, 0, s.nodes_.size()); }

StringBuilder& StringBuilder::append_range(const WorldString& s, std::size_t begin, std::size_t end) {
  if (s.alphabet_ != out_.alphabet_) throw Error("cannot mix strings of different alphabets");
  // Leading closes may end scopes opened before the range, which may now be empty: one by one.
  while (begin < end && s.nodes_[begin].kind == NodeKind::Close) {
    close();
    ++begin;
  }
  if (begin >= end) return *this;
  if (begin == 0 && end == s.nodes_.size() && out_.nodes_.empty() && open_.empty()) {
    // The whole of a string into an empty builder: a plain copy, no index to shift.
    out_.nodes_ = s.nodes_;
    out_.store_ = s.store_;
    out_.actor_count_ = s.actor_count_;
    out_.close_count_ = s.close_count_;
    return *this;
  }
  // The rest is a block copy: nodes, then their values (which are contiguous and in node order
  // in every WorldString), shifted by the difference of the stores. No scope in the block can be
  // empty: the source has none, and the block starts with a symbol.
  std::uint32_t first_value = UINT32_MAX, last_value = 0;
  for (std::size_t i = begin; i < end; ++i) {
    const Node& n = s.nodes_[i];
    if (n.kind == NodeKind::Close || n.value_count == 0) continue;
    first_value = std::min(first_value, n.first_value);
    last_value = std::max(last_value, n.first_value + n.value_count);
  }
  std::int64_t shift = 0;
  if (first_value != UINT32_MAX) {
    const std::uint32_t start = out_.store_.push_range(s.store_, first_value, last_value - first_value);
    shift = static_cast<std::int64_t>(start) - static_cast<std::int64_t>(first_value);
  }
  const std::size_t node_start = out_.nodes_.size();
  // A figure goes on across the block's start only if this string ends with a primitive.
  const bool may_join = ends_with_primitive();
  out_.nodes_.insert(out_.nodes_.end(), s.nodes_.begin() + static_cast<std::ptrdiff_t>(begin),
                     s.nodes_.begin() + static_cast<std::ptrdiff_t>(end));
  const std::uint32_t value_end = out_.store_.size();
  if (!may_join) out_.nodes_[node_start].joined = false;
  for (std::size_t k = node_start; k < out_.nodes_.size(); ++k) {
    Node& n = out_.nodes_[k];
    switch (n.kind) {
      case NodeKind::Actor: ++out_.actor_count_; break;
      case NodeKind::Transformation: open_.push_back(k); break;
      case NodeKind::Close:
        if (open_.empty()) throw Error("append_range: the range closes a scope that is not open");
        n.first_value = out_.nodes_[open_.back()].first_value;
        open_.pop_back();
        ++out_.close_count_;
        continue;
      case NodeKind::Primitive: break;
    }
    // Nodes without values keep an index at the end of the store, as the builder gives them.
    n.first_value = n.value_count ? static_cast<std::uint32_t>(static_cast<std::int64_t>(n.first_value) + shift)
                                  : value_end;
  }
  return *this;
}

StringBuilder& StringBuilder::append_node(const WorldString& s, std::size_t index) {
  const Node& n = s.nodes_[index];
  if (n.kind == NodeKind::Close) return close();
  const std::size_t at = out_.nodes_.size();
  const bool joined = n.joined && ends_with_primitive();
  const std::uint32_t first = out_.store_.push_range(s.store_, n.first_value, n.value_count);
  out_.nodes_.push_back(Node{n.symbol, first, n.value_count, n.kind, joined});
  if (n.kind == NodeKind::Actor) ++out_.actor_count_;
  if (n.kind == NodeKind::Transformation) open_.push_back(at);
  return *this;
}

WorldString StringBuilder::finish() {
  if (!open_.empty()) {
    throw Error("the string has " + std::to_string(open_.size()) + " unclosed scope(s)");
  }
  WorldString result(out_.alphabet_);
  std::swap(result, out_);
  return result;
}

}  // namespace vwg
