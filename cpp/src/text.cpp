#include "vwg/text.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "vwg/actor.hpp"
#include "vwg/error.hpp"

namespace vwg {

// ---------------------------------------------------------------------------------------------
// Printing

std::string format_real(double r) {
  // Python's repr(float): the shortest digits that round-trip, in fixed notation when the decimal
  // exponent is in [-5, 15] (a ".0" added to integers), otherwise d.ddde±XX.
  // Not a number and the infinities as Python spells them (to_chars gives them no exponent to read).
  if (std::isnan(r)) return "nan";
  if (std::isinf(r)) return r < 0 ? "-inf" : "inf";
  char buf[64];
  auto res = std::to_chars(buf, buf + sizeof buf, r, std::chars_format::scientific);
  std::string_view sci(buf, static_cast<std::size_t>(res.ptr - buf));
  std::string sign;
  if (sci.front() == '-') {
    sign = "-";
    sci.remove_prefix(1);
  }
  const std::size_t e = sci.find('e');
  std::string digits;
  for (char c : sci.substr(0, e)) {
    if (c != '.') digits += c;
  }
  int exponent = 0;
  std::from_chars(sci.data() + e + 1 + (sci[e + 1] == '+' ? 1 : 0), sci.data() + sci.size(), exponent);
  if (exponent < -4 || exponent >= 16) {
    std::string out = sign + digits.substr(0, 1);
    if (digits.size() > 1) out += "." + digits.substr(1);
    char ebuf[16];
    std::snprintf(ebuf, sizeof ebuf, "e%c%02d", exponent < 0 ? '-' : '+', exponent < 0 ? -exponent : exponent);
    return out + ebuf;
  }
  std::string out;
  if (exponent < 0) {
    out = "0." + std::string(static_cast<std::size_t>(-exponent - 1), '0') + digits;
  } else if (static_cast<std::size_t>(exponent) + 1 >= digits.size()) {
    out = digits + std::string(static_cast<std::size_t>(exponent) + 1 - digits.size(), '0') + ".0";
  } else {
    out = digits.substr(0, static_cast<std::size_t>(exponent) + 1) + "." + digits.substr(static_cast<std::size_t>(exponent) + 1);
  }
  return sign + out;
}

std::string quote_text(std::string_view s) {
  std::string out;
  out.reserve(s.size() + 2);
  out += '"';
  for (char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      case '\b': out += "\\b"; break;
      case '\f': out += "\\f"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  out += '"';
  return out;
}

std::string blob_name(const Blob& blob) {
  char buf[20];
  std::snprintf(buf, sizeof buf, "@%016llx", static_cast<unsigned long long>(blob.content_hash()));
  return buf;
}

void append_value_text(std::string& out, const ValueStore& store, const Value& v) {
  switch (v.kind) {
    case ValueKind::Int: {
      char buf[24];
      auto res = std::to_chars(buf, buf + sizeof buf, v.i);
      out.append(buf, res.ptr);
      break;
    }
    case ValueKind::Real: out += format_real(v.r); break;
    case ValueKind::Bool: out += v.b ? "true" : "false"; break;
    case ValueKind::Text: out += quote_text(store.text(v)); break;
    case ValueKind::Blob: out += blob_name(*store.blob(v)); break;
  }
}

namespace {
/// `Name` or `Name<v, ...>` (primitives, transformations) or `Name<k=v, ...>` (actors).
void append_node_text(std::string& out, const SymbolInfo& info, const ValueStore& store,
                      std::uint32_t first_value, std::size_t count) {
  out += info.name;
  if (count == 0) return;
  const bool named = info.kind == SymbolKind::Actor;
  out += '<';
  for (std::size_t k = 0; k < count; ++k) {
    if (k) out += ", ";
    if (named) {
      out += info.schema.params[k].name;
      out += '=';
    }
    append_value_text(out, store, store[first_value + static_cast<std::uint32_t>(k)]);
  }
  out += '>';
}
}  // namespace

std::string to_text(const WorldString& s) {
  std::string out;
  bool after_object = false;
  for (const Node& n : s.nodes()) {
    if (n.kind == NodeKind::Close) {
      out += ')';
      after_object = true;
      continue;
    }
    // A figure's primitives stand side by side (rule 6, FIGURE → p+); objects are joined by '.'.
    if (after_object) out += n.joined ? " " : " . ";
    append_node_text(out, s.alphabet().symbol(n.symbol), s.store(), n.first_value, n.value_count);
    if (n.kind == NodeKind::Transformation) {
      out += '(';
      after_object = false;
    } else {
      after_object = true;
    }
  }
  return out;
}

std::string to_text(const NodeView& node) {
  std::string out;
  const Node& n = node.raw();
  append_node_text(out, node.info(), node.store(), n.first_value, n.value_count);
  return out;
}

std::string to_text(const ActorState& actor) {
  std::string out;
  append_node_text(out, actor.info(), actor.store(), 0, actor.size());
  return out;
}

// ---------------------------------------------------------------------------------------------
// Parsing

namespace {

bool is_name_start(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_'; }
bool is_name_char(char c) { return is_name_start(c) || (c >= '0' && c <= '9'); }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

struct Position {
  std::size_t offset = 0, line = 1, column = 1;
};

/// One parsed parameter before it is matched to a schema.
struct RawParam {
  Position at;
  std::string key;  // empty: positional
  Datum value{0};
  std::string text;  // as written, for messages
};

class Parser {
 public:
  Parser(std::string_view text, std::string_view source, const BlobTable* blobs)
      : text_(text), source_(source), blobs_(blobs) {}

  WorldString parse_world(std::shared_ptr<const Alphabet> alphabet) {
    const Alphabet& A = *alphabet;
    StringBuilder out(alphabet);
    struct Scope {
      Position at;
      std::string name;
      std::size_t nodes_at_open;
    };
    std::vector<Scope> scopes;
    skip_space();
    if (at_end()) return out.finish();  // ε
    bool expect_object = true;
    // Juxtaposition (rule 6, FIGURE → p+): after a primitive and white space, another primitive
    // joins it in one figure. `joining` is set when such a name is next.
    bool joining = false;
    NodeKind last = NodeKind::Close;  // the kind of the object before: a primitive, an actor or a scope's end
    std::size_t object_end = 0;       // where the last primitive's or actor's text ends
    for (;;) {
      skip_space();
      const bool spaced = pos_.offset != object_end;
      if (!expect_object && !at_end() && is_name_start(peek())) {
        check_juxtaposition(A, spaced, scopes.empty(), last);
        joining = true;
        expect_object = true;
      }
      if (expect_object) {
        if (at_end() || !is_name_start(peek())) {
          if (!scopes.empty() && !at_end() && peek() == ')' && out.node_count() == scopes.back().nodes_at_open) {
            fail(here(), "an object inside the scope of '" + scopes.back().name +
                             "' (rule 5: a transformation takes t(OBJECTS), not t())");
          }
          fail(here(), "a primitive, transformation or actor name");
        }
        const Position at = here();
        const std::string name(read_name());
        object_end = pos_.offset;
        const auto id = A.find_symbol(name);
        if (!id) unknown_symbol(A, name, at);
        const SymbolInfo& info = A.symbol(*id);
        std::vector<RawParam> raw;
        skip_space();
        if (!at_end() && peek() == '<') {
          raw = parse_params();
          object_end = pos_.offset;
        }
        const auto params = match_params(info.name, info.schema, info.kind == SymbolKind::Actor ? "attribute" : "parameter", raw, at, nullptr);
        switch (info.kind) {
          case SymbolKind::Primitive:
            if (joining) {
              out.juxtapose(*id, params);
            } else {
              out.primitive(*id, params);
            }
            joining = false;
            expect_object = false;
            last = NodeKind::Primitive;
            break;
          case SymbolKind::Actor:
            out.actor(*id, params);
            expect_object = false;
            last = NodeKind::Actor;
            break;
          case SymbolKind::Transformation:
            skip_space();
            if (at_end() || peek() != '(') {
              fail(here(), "'(' after transformation '" + info.name + "' (rule 5: t(OBJECTS))");
            }
            advance(1);
            out.open(*id, params);
            scopes.push_back(Scope{at, info.name, out.node_count()});
            expect_object = true;
            break;
        }
        continue;
      }
      // After an object: a separator, the end of a scope, or the end of the text.
      if (at_end()) {
        if (!scopes.empty()) {
          const Scope& s = scopes.back();
          fail(here(), "')' to close the scope of '" + s.name + "' opened at line " +
                           std::to_string(s.at.line) + ", column " + std::to_string(s.at.column));
        }
        return out.finish();
      }
      const char c = peek();
      if (c == '.') {
        advance(1);
        expect_object = true;
      } else if (c == '\xC2' && pos_.offset + 1 < text_.size() && text_[pos_.offset + 1] == '\xB7') {
        advance(2);  // '·'
        expect_object = true;
      } else if (c == ')') {
        if (scopes.empty()) fail(here(), "'.' or end of text (no scope is open)");
        advance(1);
        out.close();
        scopes.pop_back();
        last = NodeKind::Close;
      } else if (c == '(') {
        fail(here(), scopes.empty() ? "'.' or end of text (only transformations take a scope)"
                                    : "'.' or ')' (only transformations take a scope)");
      } else {
        fail(here(), scopes.empty() ? "'.' or end of text" : "'.' or ')'");
      }
    }
  }

  /// At a name right after an object: it may only be a primitive after a primitive, with white space
  /// between them (one figure, rule 6); anything else is the error of a missing '.'.
  void check_juxtaposition(const Alphabet& A, bool spaced, bool top_level, NodeKind last) const {
    const Position at = here();
    const std::string expected = top_level ? "'.' or end of text" : "'.' or ')'";
    const std::string_view name = peek_name();
    const auto id = A.find_symbol(name);
    const char* after = nullptr;  // what the object before is, when it is no primitive
    if (last == NodeKind::Actor) after = "an actor";
    if (last != NodeKind::Primitive && last != NodeKind::Actor) after = "a transformation's scope";
    if (after) {
      fail(at, expected + " (only primitives are juxtaposed, in a figure (rule 6, FIGURE → p+); " +
                   after + " is followed by '.')");
    }
    if (!id) {
      unknown_symbol(A, std::string(name), at);
    }
    const SymbolInfo& info = A.symbol(*id);
    if (info.kind != SymbolKind::Primitive) {
      fail(at, expected + " (only primitives are juxtaposed, in a figure (rule 6, FIGURE → p+); '" + info.name +
                   "' is " + (info.kind == SymbolKind::Actor ? "an actor" : "a transformation") + ")");
    }
    if (!spaced) fail(at, expected + " (or white space between the primitives of a figure)");
  }

  void parse_event_into(EventList& out) {
    const Alphabet& A = out.alphabet();
    skip_space();
    if (at_end() || !is_name_start(peek())) fail(here(), "an event type name");
    const Position at = here();
    const std::string name(read_name());
    const auto id = A.find_event_type(name);
    if (!id) {
      std::string expected = "an event type of the alphabet";
      if (A.find_symbol(name)) expected += " ('" + name + "' is a symbol, not an event type)";
      fail(at, expected, "'" + name + "'");
    }
    const EventTypeInfo& info = A.event_type(*id);
    std::vector<RawParam> raw;
    skip_space();
    if (!at_end() && peek() == '<') raw = parse_params();
    skip_space();
    if (!at_end()) fail(here(), "end of the event");
    std::int64_t target = kNoTarget;
    const auto fields = match_params(info.name, info.fields, "field", raw, at, &target);
    out.emit(*id, fields, target);
  }

 private:
  // --- cursor -----------------------------------------------------------------------------
  bool at_end() const { return pos_.offset >= text_.size(); }
  char peek() const { return text_[pos_.offset]; }
  Position here() const { return pos_; }

  void advance(std::size_t n) {
    for (std::size_t k = 0; k < n && pos_.offset < text_.size(); ++k) {
      const char c = text_[pos_.offset++];
      if (c == '\n') {
        ++pos_.line;
        pos_.column = 1;
      } else if ((static_cast<unsigned char>(c) & 0xC0) != 0x80) {
        ++pos_.column;  // columns count characters, not UTF-8 continuation bytes
      }
    }
  }

  void skip_space() {
    while (!at_end()) {
      const char c = peek();
      if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
        advance(1);
      } else if (c == '#') {
        while (!at_end() && peek() != '\n') advance(1);
      } else {
        break;
      }
    }
  }

  // ---- public: the first check of any text parsed -----------------------------------------------
 public:
  /// Refuse text that is not UTF-8 (a byte that starts no character, a cut or overlong sequence, an
  /// encoded surrogate), naming the line and column of the first bad byte: what is parsed must print.
  void check_utf8() {
    std::size_t line = 1, column = 1;  // column in characters, as advance() counts it
    const auto* b = reinterpret_cast<const unsigned char*>(text_.data());
    for (std::size_t i = 0; i < text_.size();) {
      const unsigned char c = b[i];
      std::size_t n = c < 0x80 ? 1 : (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : (c & 0xF8) == 0xF0 ? 4 : 0;
      bool ok = n != 0 && i + n <= text_.size();
      for (std::size_t k = 1; ok && k < n; ++k) ok = (b[i + k] & 0xC0) == 0x80;
      if (ok && n == 2) ok = c >= 0xC2;                                    // overlong
      if (ok && n == 3) ok = !(c == 0xE0 && b[i + 1] < 0xA0) && !(c == 0xED && b[i + 1] >= 0xA0);  // overlong, surrogate
      if (ok && n == 4) ok = !(c == 0xF0 && b[i + 1] < 0x90) && (c < 0xF4 || (c == 0xF4 && b[i + 1] < 0x90));
      if (!ok) {
        char found[48];
        const bool surrogate = c == 0xED && i + 2 < text_.size() && b[i + 1] >= 0xA0 && b[i + 1] < 0xC0 &&
                               (b[i + 2] & 0xC0) == 0x80;
        if (surrogate) {  // what Python's surrogateescape and surrogatepass make of a lone surrogate
          const unsigned cp = 0xD000u | ((b[i + 1] & 0x3Fu) << 6) | (b[i + 2] & 0x3Fu);
          std::snprintf(found, sizeof found, "U+%04X (a lone surrogate)", cp);
        } else {
          std::snprintf(found, sizeof found, "the byte 0x%02X", static_cast<unsigned>(c));
        }
        throw ParseError(std::string(source_), line, column, found, "text in UTF-8", "");
      }
      if (c == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
      i += n;
    }
  }

 private:
  /// The name at the cursor, which stays where it is.
  std::string_view peek_name() const {
    std::size_t end = pos_.offset;
    while (end < text_.size() && is_name_char(text_[end])) ++end;
    return text_.substr(pos_.offset, end - pos_.offset);
  }

  std::string_view read_name() {
    const std::size_t start = pos_.offset;
    while (!at_end() && is_name_char(peek())) advance(1);
    return text_.substr(start, pos_.offset - start);
  }

  std::string line_text(const Position& at) const {
    std::size_t begin = at.offset;
    while (begin > 0 && text_[begin - 1] != '\n') --begin;
    std::size_t end = at.offset;
    while (end < text_.size() && text_[end] != '\n' && text_[end] != '\r') ++end;
    std::string line(text_.substr(begin, end - begin));
    if (line.size() > 200) {
      // Cut before a character, not inside one: the excerpt stays valid UTF-8.
      std::size_t cut = 200;
      while (cut > 0 && (static_cast<unsigned char>(line[cut]) & 0xC0) == 0x80) --cut;
      line = line.substr(0, cut) + "...";
    }
    return line;
  }

  /// What stands at `at`, for the "found" part of a message.
  std::string describe(const Position& at) const {
    if (at.offset >= text_.size()) return "end of text";
    const char c = text_[at.offset];
    if (is_name_start(c)) {
      std::size_t end = at.offset;
      while (end < text_.size() && is_name_char(text_[end])) ++end;
      return "'" + std::string(text_.substr(at.offset, end - at.offset)) + "'";
    }
    if (c == '\n' || c == '\r') return "end of line";
    std::size_t len = 1;
    while (len < 4 && at.offset + len < text_.size() &&
           (static_cast<unsigned char>(text_[at.offset + len]) & 0xC0) == 0x80) {
      ++len;
    }
    return "'" + std::string(text_.substr(at.offset, len)) + "'";
  }

  [[noreturn]] void fail(const Position& at, const std::string& expected, std::string found = {}) const {
    if (found.empty()) found = describe(at);
    throw ParseError(std::string(source_), at.line, at.column, found, expected, line_text(at));
  }

  [[noreturn]] void unknown_symbol(const Alphabet& A, const std::string& name, const Position& at) const {
    std::string expected = "a primitive, transformation or actor of the alphabet";
    if (A.find_event_type(name)) {
      expected += " ('" + name + "' is an event type)";
    } else {
      std::string best;
      std::size_t best_d = 3;
      for (const auto& s : A.symbols()) {
        const std::size_t d = edit_distance(s.name, name);
        if (d < best_d) {
          best_d = d;
          best = s.name;
        }
      }
      if (!best.empty()) expected += "; did you mean '" + best + "'?";
    }
    fail(at, expected, "unknown symbol '" + name + "'");
  }

  // --- parameters -------------------------------------------------------------------------
  std::vector<RawParam> parse_params() {
    std::vector<RawParam> out;
    advance(1);  // '<'
    skip_space();
    if (!at_end() && peek() == '>') {
      advance(1);
      return out;
    }
    for (;;) {
      skip_space();
      RawParam p;
      p.at = here();
      // A key is a name followed by '='; `true` / `false` alone are values.
      if (!at_end() && is_name_start(peek())) {
        const Position save = pos_;
        const std::string name(read_name());
        skip_space();
        if (!at_end() && peek() == '=') {
          advance(1);
          skip_space();
          p.key = name;
        } else {
          pos_ = save;
        }
      }
      const Position value_at = here();
      p.value = parse_value();
      p.text = std::string(text_.substr(value_at.offset, pos_.offset - value_at.offset));
      if (!p.key.empty()) p.at = value_at;
      out.push_back(std::move(p));
      skip_space();
      if (at_end()) fail(here(), "',' or '>'");
      if (peek() == ',') {
        advance(1);
        continue;
      }
      if (peek() == '>') {
        advance(1);
        return out;
      }
      fail(here(), "',' or '>'");
    }
  }

  Datum parse_value() {
    if (at_end()) fail(here(), "a value (number, \"text\", true, false or @blob)");
    const char c = peek();
    const Position at = here();
    if (c == '"') return Datum(parse_text());
    if (c == '@') {
      advance(1);
      const std::size_t start = pos_.offset;
      while (!at_end() && is_name_char(peek())) advance(1);
      const std::string key(text_.substr(start, pos_.offset - start));
      if (key.empty()) fail(here(), "a blob name after '@'");
      if (!blobs_) fail(at, "a value (this text has no blob table, so '@' references cannot be resolved)", "'@" + key + "'");
      auto it = blobs_->find(key);
      if (it == blobs_->end()) fail(at, "a blob of the blob table given with the text", "unknown blob '@" + key + "'");
      return Datum(it->second);
    }
    if (c == '-' || c == '+' || c == '.' || is_digit(c)) return parse_number();
    if (is_name_start(c)) {
      const std::string word(read_name());
      if (word == "true") return Datum(true);
      if (word == "false") return Datum(false);
      fail(at, "a value (number, \"text\", true, false or @blob)", "'" + word + "'");
    }
    fail(at, "a value (number, \"text\", true, false or @blob)");
  }

  Datum parse_number() {
    const Position at = here();
    std::size_t i = pos_.offset;
    if (text_[i] == '+' || text_[i] == '-') ++i;
    bool real = false, digits = false;
    while (i < text_.size() && is_digit(text_[i])) ++i, digits = true;
    if (i < text_.size() && text_[i] == '.') {
      real = true;
      ++i;
      while (i < text_.size() && is_digit(text_[i])) ++i, digits = true;
    }
    if (digits && i < text_.size() && (text_[i] == 'e' || text_[i] == 'E')) {
      std::size_t j = i + 1;
      if (j < text_.size() && (text_[j] == '+' || text_[j] == '-')) ++j;
      if (j < text_.size() && is_digit(text_[j])) {
        real = true;
        i = j;
        while (i < text_.size() && is_digit(text_[i])) ++i;
      }
    }
    std::string_view lexeme = text_.substr(pos_.offset, i - pos_.offset);
    if (!digits) fail(at, "a number", "'" + std::string(lexeme) + "'");
    // from_chars takes no leading '+'.
    std::string_view digits_part = lexeme[0] == '+' ? lexeme.substr(1) : lexeme;
    advance(i - pos_.offset);
    if (real) {
      double r = 0;
      auto res = std::from_chars(digits_part.data(), digits_part.data() + digits_part.size(), r);
      if (res.ec != std::errc() || res.ptr != digits_part.data() + digits_part.size() || !std::isfinite(r)) {
        fail(at, "a finite real number", "'" + std::string(lexeme) + "'");
      }
      return Datum(r);
    }
    std::int64_t v = 0;
    auto res = std::from_chars(digits_part.data(), digits_part.data() + digits_part.size(), v);
    if (res.ec != std::errc() || res.ptr != digits_part.data() + digits_part.size()) {
      fail(at, "an integer in the 64-bit range", "'" + std::string(lexeme) + "'");
    }
    return Datum(v);
  }

  std::string parse_text() {
    const Position open = here();
    advance(1);  // '"'
    std::string out;
    for (;;) {
      if (at_end() || peek() == '\n' || peek() == '\r') {
        fail(here(), "'\"' to end the text that starts at line " + std::to_string(open.line) +
                         ", column " + std::to_string(open.column));
      }
      const char c = peek();
      if (c == '"') {
        advance(1);
        return out;
      }
      if (c != '\\') {
        out += c;
        advance(1);
        continue;
      }
      const Position esc = here();
      advance(1);
      if (at_end()) fail(here(), "an escape character after '\\'");
      const char e = peek();
      advance(1);
      switch (e) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'n': out += '\n'; break;
        case 't': out += '\t'; break;
        case 'r': out += '\r'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'u': {
          std::uint32_t cp = read_hex4(esc);
          if (cp >= 0xDC00 && cp <= 0xDFFF) {
            fail(esc, "a character (a low surrogate \\uDC00-\\uDFFF comes only after a high one)");
          }
          if (cp >= 0xD800 && cp <= 0xDBFF) {
            if (pos_.offset + 1 < text_.size() && peek() == '\\' && text_[pos_.offset + 1] == 'u') {
              advance(2);
              const std::uint32_t lo = read_hex4(esc);
              if (lo < 0xDC00 || lo > 0xDFFF) fail(esc, "a low surrogate after a high surrogate");
              cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
            } else {
              fail(esc, "a low surrogate after a high surrogate");
            }
          }
          append_utf8(out, cp);
          break;
        }
        default:
          fail(esc, "an escape: \\\" \\\\ \\/ \\n \\t \\r \\b \\f or \\uXXXX");
      }
    }
  }

  std::uint32_t read_hex4(const Position& esc) {
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) {
      if (at_end()) fail(esc, "four hex digits after \\u");
      const char h = peek();
      v <<= 4;
      if (h >= '0' && h <= '9') v |= static_cast<std::uint32_t>(h - '0');
      else if (h >= 'a' && h <= 'f') v |= static_cast<std::uint32_t>(h - 'a' + 10);
      else if (h >= 'A' && h <= 'F') v |= static_cast<std::uint32_t>(h - 'A' + 10);
      else fail(esc, "four hex digits after \\u");
      advance(1);
    }
    return v;
  }

  static void append_utf8(std::string& out, std::uint32_t cp) {
    if (cp < 0x80) {
      out += static_cast<char>(cp);
    } else if (cp < 0x800) {
      out += static_cast<char>(0xC0 | (cp >> 6));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
      out += static_cast<char>(0xE0 | (cp >> 12));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (cp >> 18));
      out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    }
  }

  static std::string kind_and_text(const RawParam& p) {
    return std::string(kind_name(p.value.kind())) + " " + p.text;
  }

  /// Match parsed parameters to a schema: positional first, then by name; fill defaults; check
  /// kinds. `target`, when given, accepts the reserved event key `to`.
  std::vector<Datum> match_params(const std::string& owner, const Schema& schema, const char* what,
                                  const std::vector<RawParam>& raw, const Position& owner_at,
                                  std::int64_t* target) const {
    std::vector<Datum> out;
    if (schema.variadic) {
      for (const RawParam& p : raw) {
        if (!p.key.empty()) {
          fail(p.at, "a positional parameter ('" + owner + "' declares no parameter names)",
               "'" + p.key + "='");
        }
        out.push_back(p.value);
      }
      return out;
    }
    const auto& specs = schema.params;
    std::vector<std::optional<Datum>> slots(specs.size());
    std::vector<const RawParam*> given(specs.size(), nullptr);
    bool seen_key = false;
    std::size_t next_positional = 0;
    for (const RawParam& p : raw) {
      std::size_t index;
      if (p.key.empty()) {
        if (seen_key) fail(p.at, "a " + std::string(what) + " name (positional values come before named ones)");
        if (next_positional >= specs.size()) {
          fail(p.at, "'>' ('" + owner + "' takes " + std::to_string(specs.size()) + " " + what + "s)");
        }
        index = next_positional++;
      } else {
        seen_key = true;
        if (target && p.key == "to") {
          if (p.value.kind() != ValueKind::Int) fail(p.at, "an integer actor id for 'to'", kind_and_text(p));
          *target = p.value.as_int();
          continue;
        }
        const int i = schema.index_of(p.key);
        if (i < 0) {
          std::string names;
          for (const auto& s : specs) names += (names.empty() ? "" : ", ") + s.name;
          fail(p.at, "a " + std::string(what) + " of '" + owner + "' (" + (names.empty() ? "it has none" : names) + ")",
               "'" + p.key + "'");
        }
        index = static_cast<std::size_t>(i);
      }
      if (given[index]) fail(p.at, "each " + std::string(what) + " once", "'" + specs[index].name + "' given twice");
      given[index] = &p;
      Datum v = p.value;
      const ParamSpec& spec = specs[index];
      if (v.kind() == ValueKind::Int && spec.kind == ValueKind::Real) v = Datum(static_cast<double>(v.as_int()));
      if (v.kind() != spec.kind) {
        fail(p.at, std::string(kind_name(spec.kind)) + " for " + owner + "." + spec.name, kind_and_text(p));
      }
      slots[index] = std::move(v);
    }
    out.reserve(specs.size());
    for (std::size_t i = 0; i < specs.size(); ++i) {
      if (slots[i]) {
        out.push_back(std::move(*slots[i]));
      } else if (specs[i].default_value) {
        out.push_back(*specs[i].default_value);
      } else {
        fail(owner_at, std::string(what) + " '" + specs[i].name + "' of '" + owner + "' (it has no default)",
             "'" + owner + "' without it");
      }
    }
    return out;
  }

  std::string_view text_, source_;
  const BlobTable* blobs_;
  Position pos_;
};

}  // namespace

WorldString parse_string(std::shared_ptr<const Alphabet> alphabet, std::string_view text,
                         std::string_view source, const BlobTable* blobs) {
  Parser p(text, source, blobs);
  p.check_utf8();
  return p.parse_world(std::move(alphabet));
}

void parse_event(EventList& out, std::string_view text, std::string_view source, const BlobTable* blobs) {
  Parser p(text, source, blobs);
  p.check_utf8();
  p.parse_event_into(out);
}

}  // namespace vwg
