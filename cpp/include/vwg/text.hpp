// The text form of strings and events (DESIGN.md "Text form"), parsed and printed:
//
//   world   := [object (sep object)*]            sep := '.' | '·'
//   object  := figure | NAME ['<' params '>'] ['(' object (sep object)* ')']   only transformations take '('
//   figure  := primitive (SPACE primitive)*      rule 6 (FIGURE → p+): primitives side by side
//   params  := [param (',' param)*]              param := [NAME '='] value
//   value   := integer | real | "text" | true | false | @blob
//
// A figure's primitives are separated by white space (or a comment) only: `Robot<1> Lamp`. Only
// primitives are juxtaposed; an actor or a transformation next to anything is an error that asks
// for '.'. Comments run from '#' to the end of the line. Printing is canonical: primitives and
// transformations print their parameters positionally, actors and events by name, reals always
// with a '.' or exponent (0.5, 3.0, 1e+21), separators as " . " and ", ", a figure's primitives
// with " " between them.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <string_view>

#include "vwg/event.hpp"
#include "vwg/world_string.hpp"

namespace vwg {

/// Blobs a text may refer to, by name: `@<16 hex digits>` (their content hash, as printed) or any
/// other key the caller chose.
using BlobTable = std::map<std::string, std::shared_ptr<const Blob>, std::less<>>;

/// Parse a world string. `source` names the text in errors (a file name, "<string>").
/// Throws ParseError with line, column, what was found and what was expected.
WorldString parse_string(std::shared_ptr<const Alphabet> alphabet, std::string_view text,
                         std::string_view source = "<string>", const BlobTable* blobs = nullptr);

/// Parse one event, e.g. `eLaser<to=2, dist=1.5, angle=0.1>`, appending it to `out`.
void parse_event(EventList& out, std::string_view text, std::string_view source = "<event>",
                 const BlobTable* blobs = nullptr);

/// Text of a real number as the text form prints it: shortest round-trip, always with '.' or 'e'.
std::string format_real(double r);
/// Text of a string literal with quotes and escapes.
std::string quote_text(std::string_view s);
/// `@` and the blob's content hash in 16 hex digits.
std::string blob_name(const Blob& blob);

/// Append the text of value `v` of `store` to `out`.
void append_value_text(std::string& out, const ValueStore& store, const Value& v);

}  // namespace vwg
