#include "vwg/value.hpp"

#include <cmath>
#include <cstring>
#include <string>

#include "vwg/error.hpp"
#include "vwg/hash.hpp"

namespace vwg {

std::string_view kind_name(ValueKind kind) {
  switch (kind) {
    case ValueKind::Int: return "int";
    case ValueKind::Real: return "real";
    case ValueKind::Bool: return "bool";
    case ValueKind::Text: return "text";
    case ValueKind::Blob: return "blob";
  }
  return "?";
}

double Datum::as_number() const {
  if (kind() == ValueKind::Int) return static_cast<double>(as_int());
  return as_real();
}

bool Datum::operator==(const Datum& other) const {
  if (kind() != other.kind()) return false;
  if (kind() == ValueKind::Blob) {
    const auto& a = as_blob();
    const auto& b = other.as_blob();
    if (!a || !b) return a == b;
    return a->same_content(*b);
  }
  return v_ == other.v_;
}

int Schema::index_of(std::string_view name) const {
  for (std::size_t i = 0; i < params.size(); ++i) {
    if (params[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

Datum coerce(const ParamSpec& spec, Datum value, std::string_view owner) {
  const std::string field = std::string(owner) + "." + spec.name;
  if (value.kind() == ValueKind::Int && spec.kind == ValueKind::Real) {
    value = Datum(static_cast<double>(value.as_int()));
  }
  if (value.kind() != spec.kind) {
    throw SchemaError(field, "expected " + std::string(kind_name(spec.kind)) + ", got " +
                                 std::string(kind_name(value.kind())));
  }
  if (value.kind() == ValueKind::Real && !std::isfinite(value.as_real())) {
    throw SchemaError(field, "expected a finite real, got " + std::to_string(value.as_real()));
  }
  if (value.kind() == ValueKind::Blob && !value.as_blob()) {
    throw SchemaError(field, "expected a blob, got a null reference");
  }
  return value;
}

std::uint32_t ValueStore::push_int(std::int64_t i) {
  Value v{};
  v.kind = ValueKind::Int;
  v.i = i;
  values_.push_back(v);
  return size() - 1;
}
std::uint32_t ValueStore::push_real(double r) {
  Value v{};
  v.kind = ValueKind::Real;
  v.r = r;
  values_.push_back(v);
  return size() - 1;
}
std::uint32_t ValueStore::push_bool(bool b) {
  Value v{};
  v.kind = ValueKind::Bool;
  v.b = b;
  values_.push_back(v);
  return size() - 1;
}
std::uint32_t ValueStore::push_text(std::string_view s) {
  Value v{};
  v.kind = ValueKind::Text;
  v.text.offset = static_cast<std::uint32_t>(chars_.size());
  v.text.length = static_cast<std::uint32_t>(s.size());
  chars_.append(s);
  values_.push_back(v);
  return size() - 1;
}
std::uint32_t ValueStore::push_blob(std::shared_ptr<const Blob> blob) {
  Value v{};
  v.kind = ValueKind::Blob;
  // A slot per reference, never shared by two values: the engine tells a blob it may write in place
  // by its reference count (ActorState::edit_blob), which a slot serving two actors would hide.
  v.blob = static_cast<std::uint32_t>(blobs_.size());
  blobs_.push_back(std::move(blob));
  values_.push_back(v);
  return size() - 1;
}

std::uint32_t ValueStore::push(const Datum& d) {
  switch (d.kind()) {
    case ValueKind::Int: return push_int(d.as_int());
    case ValueKind::Real: return push_real(d.as_real());
    case ValueKind::Bool: return push_bool(d.as_bool());
    case ValueKind::Text: return push_text(d.as_text());
    case ValueKind::Blob: return push_blob(d.as_blob());
  }
  return 0;
}

std::uint32_t ValueStore::push_from(const ValueStore& src, const Value& v) {
  switch (v.kind) {
    case ValueKind::Text: return push_text(src.text(v));
    case ValueKind::Blob: return push_blob(src.blob(v));
    default:
      values_.push_back(v);
      return size() - 1;
  }
}

std::uint32_t ValueStore::push_range(const ValueStore& src, std::uint32_t first, std::uint32_t count) {
  const std::uint32_t start = size();
  values_.insert(values_.end(), src.values_.begin() + first, src.values_.begin() + first + count);
  // Numbers and booleans are copied as they are; text and blobs are re-homed in this store.
  if (src.chars_.empty() && src.blobs_.empty()) return start;  // numbers only: the block copy is all
  for (std::uint32_t k = start; k < start + count; ++k) {
    Value& v = values_[k];
    if (v.kind == ValueKind::Text) {
      const std::string_view s = src.text(v);
      v.text.offset = static_cast<std::uint32_t>(chars_.size());
      chars_.append(s);
    } else if (v.kind == ValueKind::Blob) {
      std::shared_ptr<const Blob> blob = src.blob(v);  // read before v.blob is re-homed
      v.blob = static_cast<std::uint32_t>(blobs_.size());  // a slot per reference (see push_blob)
      blobs_.push_back(std::move(blob));
    }
  }
  return start;
}

void ValueStore::set(std::uint32_t i, const Datum& d) {
  if (values_[i].kind == ValueKind::Blob && d.kind() == ValueKind::Blob) {  // the slot is this value's alone
    blobs_[values_[i].blob] = d.as_blob();
    return;
  }
  push(d);
  values_[i] = values_.back();
  values_.pop_back();
}

Datum ValueStore::datum(const Value& v) const {
  switch (v.kind) {
    case ValueKind::Int: return Datum(v.i);
    case ValueKind::Real: return Datum(v.r);
    case ValueKind::Bool: return Datum(v.b);
    case ValueKind::Text: return Datum(text(v));
    case ValueKind::Blob: return Datum(blob(v));
  }
  return Datum(0);
}

bool ValueStore::equal(const ValueStore& a, const Value& va, const ValueStore& b, const Value& vb) {
  if (va.kind != vb.kind) return false;
  switch (va.kind) {
    case ValueKind::Int: return va.i == vb.i;
    // Bitwise, so that -0.0 and 0.0 differ as their texts do.
    case ValueKind::Real: return std::memcmp(&va.r, &vb.r, sizeof(double)) == 0;
    case ValueKind::Bool: return va.b == vb.b;
    case ValueKind::Text: return a.text(va) == b.text(vb);
    case ValueKind::Blob: return a.blob(va)->same_content(*b.blob(vb));
  }
  return false;
}

std::uint64_t ValueStore::hash(const Value& v) const {
  std::uint64_t h = static_cast<std::uint64_t>(v.kind) + 1;
  switch (v.kind) {
    case ValueKind::Int: return hash_combine(h, static_cast<std::uint64_t>(v.i));
    case ValueKind::Real: {
      std::uint64_t bits;
      std::memcpy(&bits, &v.r, 8);
      return hash_combine(h, bits);
    }
    case ValueKind::Bool: return hash_combine(h, v.b ? 1 : 0);
    case ValueKind::Text: {
      const auto s = text(v);
      return hash_bytes(s.data(), s.size(), h);
    }
    case ValueKind::Blob: return hash_combine(h, blob(v)->content_hash());
  }
  return h;
}

}  // namespace vwg
