// The world string w ∈ L(M) as a flat array of nodes: a transformation node opens a scope that a
// Close node ends, so `Move<1>(Robot . A)` is [T Move][P Robot][A A][Close]. A figure of several
// primitives side by side (rule 6, FIGURE → p+), `Robot Lamp`, is [P Robot][P Lamp, joined]: its
// primitives are nodes of their own, the second and later marked as joined to the one before.
// Parameters live in one ValueStore. No heap object per symbol; copying a run of nodes is a block copy.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "vwg/alphabet.hpp"
#include "vwg/value.hpp"

namespace vwg {

class ActorState;

enum class NodeKind : std::uint8_t { Primitive, Transformation, Actor, Close };

struct Node {
  SymbolId symbol;            ///< for Close: the transformation it closes
  std::uint32_t first_value;  ///< for Close: the same values as its transformation
  std::uint16_t value_count;
  NodeKind kind;
  /// A primitive juxtaposed to the primitive just before it, in one figure (rule 6, FIGURE → p+):
  /// printed `Robot Lamp`, not `Robot . Lamp`. Only a primitive right after a primitive is joined
  /// (StringBuilder keeps it so); φ and η treat the figure's primitives one by one, in order.
  bool joined = false;
};
// The flag sits in what was padding: a node stays 12 bytes.
static_assert(sizeof(Node) == 12, "Node must stay 12 bytes (the joined flag lives in its padding)");

/// A read-only view of one node with its parameters.
class NodeView {
 public:
  NodeView(const class WorldString& s, std::size_t index);
  NodeKind kind() const { return node_->kind; }
  SymbolId symbol() const { return node_->symbol; }
  /// Juxtaposed to the primitive before it, in one figure (Node::joined).
  bool joined() const { return node_->joined; }
  const SymbolInfo& info() const;
  std::size_t value_count() const { return node_->value_count; }
  const Value& value(std::size_t i) const;
  Datum datum(std::size_t i) const;
  /// Int or Real parameter i as a double.
  double number(std::size_t i) const;
  const ValueStore& store() const;
  std::size_t index() const { return index_; }
  const Node& raw() const { return *node_; }

 private:
  const class WorldString* s_;
  const Node* node_;
  std::size_t index_;
};

class WorldString {
 public:
  /// The empty string ε of the given alphabet.
  explicit WorldString(std::shared_ptr<const Alphabet> alphabet);

  const Alphabet& alphabet() const { return *alphabet_; }
  const std::shared_ptr<const Alphabet>& alphabet_ptr() const { return alphabet_; }

  bool empty() const { return nodes_.empty(); }
  /// Number of symbols (primitives, transformations, actors); scope closes are not counted.
  std::size_t symbol_count() const { return nodes_.size() - close_count_; }
  std::size_t actor_count() const { return actor_count_; }
  std::span<const Node> nodes() const { return nodes_; }
  NodeView node(std::size_t i) const { return NodeView(*this, i); }
  const ValueStore& store() const { return store_; }

  /// Structural and value equality (same alphabet object required).
  bool operator==(const WorldString& other) const;
  /// Stable hash of the content (symbols by name, values by content): equal strings hash equal,
  /// across processes and machines.
  std::uint64_t content_hash() const;

 private:
  friend class StringBuilder;
  std::shared_ptr<const Alphabet> alphabet_;
  std::vector<Node> nodes_;
  ValueStore store_;
  std::size_t actor_count_ = 0;
  std::size_t close_count_ = 0;
};

/// Builds a WorldString left to right. Parameters given as Datum are checked against the
/// symbol's schema (missing trailing ones take their defaults); copies from other strings are not
/// re-checked.
class StringBuilder {
 public:
  explicit StringBuilder(std::shared_ptr<const Alphabet> alphabet);

  StringBuilder& primitive(SymbolId id, std::span<const Datum> params = {});
  StringBuilder& primitive(std::string_view name, std::initializer_list<Datum> params = {});
  /// A primitive juxtaposed to the primitive just appended, in one figure with it (rule 6,
  /// FIGURE → p+; the text `Robot Lamp`). Throws if the string does not end with a primitive.
  StringBuilder& juxtapose(SymbolId id, std::span<const Datum> params = {});
  StringBuilder& juxtapose(std::string_view name, std::initializer_list<Datum> params = {});
  /// β side of a scope: `t<params>(`. Must be matched by close().
  StringBuilder& open(SymbolId id, std::span<const Datum> params = {});
  StringBuilder& open(std::string_view name, std::initializer_list<Datum> params = {});
  /// `)`: ends the innermost open scope. A scope left empty is removed with its transformation
  /// (t(ε) is not in L(M); see DESIGN.md, "empty scopes").
  StringBuilder& close();
  StringBuilder& actor(SymbolId id, std::span<const Datum> attributes = {});
  StringBuilder& actor(std::string_view name, std::initializer_list<Datum> attributes = {});
  StringBuilder& actor(const ActorState& state);
  /// Append all of `s` (same alphabet).
  StringBuilder& append(const WorldString& s);
  /// Append nodes [begin, end) of `s` as a block. The range may close scopes this builder opened
  /// earlier and may leave scopes open; a scope it leaves empty is removed as close() does. Nodes
  /// keep their figures (Node::joined), except that a first node joined in `s` is joined here only
  /// if this string ends with a primitive.
  StringBuilder& append_range(const WorldString& s, std::size_t begin, std::size_t end);
  /// Append one node of `s` (a Close node closes the innermost open scope of this builder). A joined
  /// primitive stays joined only after a primitive.
  StringBuilder& append_node(const WorldString& s, std::size_t index);

  std::size_t depth() const { return open_.size(); }
  const Alphabet& alphabet() const { return out_.alphabet(); }
  const std::shared_ptr<const Alphabet>& alphabet_ptr() const { return out_.alphabet_ptr(); }
  /// Value k of node `node` built so far, for in-place updates of numbers (batch λ).
  Value& value(std::size_t node, std::size_t k) {
    return out_.store_[out_.nodes_[node].first_value + static_cast<std::uint32_t>(k)];
  }
  const Node& node(std::size_t index) const { return out_.nodes_[index]; }
  std::size_t node_count() const { return out_.nodes_.size(); }
  std::size_t actor_count() const { return out_.actor_count_; }
  void reserve(std::size_t nodes, std::size_t values, std::size_t chars);
  /// The string built so far; throws if a scope is still open. The builder is reset.
  WorldString finish();

  /// Parameters of one symbol checked against its schema (used by the parser too).
  static std::vector<Datum> check_params(const SymbolInfo& info, std::span<const Datum> params);

 private:
  void push_node(SymbolId id, NodeKind kind, std::span<const Datum> params, bool joined = false);
  /// Whether a joined primitive may come next: the string built so far ends with a primitive.
  bool ends_with_primitive() const;
  WorldString out_;
  std::vector<std::size_t> open_;  // node indices of open transformations
};

/// Canonical text of a string, e.g. `Move<0.5>(Robot Lamp) . ARobot<id=1, row=3>` (see text.hpp).
std::string to_text(const WorldString& s);
/// Canonical text of one node alone, without its scope, e.g. `Move<0.5>`.
std::string to_text(const NodeView& node);

}  // namespace vwg
