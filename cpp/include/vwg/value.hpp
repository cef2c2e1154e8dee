// Parameter and attribute values: the owned `Datum` used at API boundaries, and the compact
// `Value` stored in flat arrays inside strings and event lists (no heap object per value).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "vwg/blob.hpp"

namespace vwg {

/// The five kinds of values a parameter, attribute or event field can hold.
enum class ValueKind : std::uint8_t { Int, Real, Bool, Text, Blob };

/// "int", "real", "bool", "text" or "blob".
std::string_view kind_name(ValueKind kind);

/// An owned value, used to build strings and events and to read them out.
class Datum {
 public:
  Datum(int v) : v_(std::int64_t{v}) {}
  Datum(long v) : v_(std::int64_t{v}) {}
  Datum(long long v) : v_(std::int64_t{v}) {}
  Datum(unsigned v) : v_(std::int64_t{v}) {}
  Datum(double v) : v_(v) {}
  Datum(bool v) : v_(v) {}
  Datum(const char* v) : v_(std::string(v)) {}
  Datum(std::string v) : v_(std::move(v)) {}
  Datum(std::string_view v) : v_(std::string(v)) {}
  Datum(std::shared_ptr<const Blob> v) : v_(std::move(v)) {}

  ValueKind kind() const { return static_cast<ValueKind>(v_.index()); }
  std::int64_t as_int() const { return std::get<0>(v_); }
  double as_real() const { return std::get<1>(v_); }
  /// Int or Real as a double.
  double as_number() const;
  bool as_bool() const { return std::get<2>(v_); }
  const std::string& as_text() const { return std::get<3>(v_); }
  const std::shared_ptr<const Blob>& as_blob() const { return std::get<4>(v_); }

  /// Equal kind and content (blobs by content).
  bool operator==(const Datum& other) const;

 private:
  // The order matches ValueKind.
  std::variant<std::int64_t, double, bool, std::string, std::shared_ptr<const Blob>> v_;
};

/// One declared parameter (of a primitive or transformation), attribute (of an actor) or field
/// (of an event type): a name, a kind and an optional default (no default means required).
struct ParamSpec {
  std::string name;
  ValueKind kind = ValueKind::Real;
  std::optional<Datum> default_value;
};

/// The parameter list of a symbol or event type. `variadic` schemas take any number of positional
/// values of any kind (a primitive declared by name only).
struct Schema {
  std::vector<ParamSpec> params;
  bool variadic = false;

  static Schema any() { return Schema{{}, true}; }
  /// Index of the parameter called `name`, or -1.
  int index_of(std::string_view name) const;
};

/// Check `value` against `spec`, widening Int to Real; throws SchemaError naming `owner.name`.
/// Reals must be finite.
Datum coerce(const ParamSpec& spec, Datum value, std::string_view owner);

/// A value as stored in a ValueStore: 16 bytes, text and blobs by index into the store.
struct Value {
  ValueKind kind;
  union {
    std::int64_t i;
    double r;
    bool b;
    struct {
      std::uint32_t offset, length;
    } text;
    std::uint32_t blob;
  };
};

/// The values of a string or event list in flat arrays: values, the characters of text values,
/// and the blobs they refer to.
class ValueStore {
 public:
  std::uint32_t size() const { return static_cast<std::uint32_t>(values_.size()); }
  const Value& operator[](std::uint32_t i) const { return values_[i]; }
  Value& operator[](std::uint32_t i) { return values_[i]; }

  /// Append an owned value; returns its index.
  std::uint32_t push(const Datum& d);
  /// Append a value that lives in another store (text and blob re-homed here).
  std::uint32_t push_from(const ValueStore& src, const Value& v);
  /// Append `count` values of `src` starting at `first`; returns the index of the first copy.
  std::uint32_t push_range(const ValueStore& src, std::uint32_t first, std::uint32_t count);
  /// Overwrite value `i` with an owned value (its old text characters become garbage).
  void set(std::uint32_t i, const Datum& d);
  /// Forget the values from index `n` on (text characters and blobs are left; they are garbage).
  void truncate(std::uint32_t n) { values_.resize(n); }
  void reserve(std::size_t values, std::size_t chars) {
    values_.reserve(values);
    chars_.reserve(chars);
  }
  void clear() {
    values_.clear();
    chars_.clear();
    blobs_.clear();
  }

  std::string_view text(const Value& v) const { return {chars_.data() + v.text.offset, v.text.length}; }
  const std::shared_ptr<const Blob>& blob(const Value& v) const { return blobs_[v.blob]; }
  Datum datum(const Value& v) const;
  /// Content equality of two values, each read in its own store.
  static bool equal(const ValueStore& a, const Value& va, const ValueStore& b, const Value& vb);
  /// Hash of a value's content, stable across stores.
  std::uint64_t hash(const Value& v) const;

  std::size_t chars_size() const { return chars_.size(); }

  /// Direct construction helpers used by the parser and builders.
  std::uint32_t push_int(std::int64_t i);
  std::uint32_t push_real(double r);
  std::uint32_t push_bool(bool b);
  std::uint32_t push_text(std::string_view s);
  std::uint32_t push_blob(std::shared_ptr<const Blob> blob);

 private:
  std::vector<Value> values_;
  std::string chars_;
  std::vector<std::shared_ptr<const Blob>> blobs_;
};

}  // namespace vwg
