#include <cmath>
#include <gtest/gtest.h>

#include <cstring>

#include "helpers.hpp"
#include "vwg/hash.hpp"

using namespace vwg;
using namespace vwg::testing;

namespace {
std::shared_ptr<Alphabet> case_study_alphabet() {
  auto a = std::make_shared<Alphabet>();
  a->add_primitive("Robot", schema({integer("id", 0)}));
  a->add_primitive("Lamp");  // variadic
  a->add_transformation("Move", schema({real("dist")}));
  a->add_transformation("Rotate", schema({real("angle")}));
  a->add_event_type("tick", false);
  a->add_event_type("eLaser", false, schema({real("dist"), real("angle")}));
  a->add_actor("ARobot", {"tick"},
               Schema{{integer("id", 0), integer("row"), integer("column"), real("angle", 0.0),
                       ParamSpec{"objective", ValueKind::Text, Datum("")}},
                      false},
               nullptr);
  return a;
}

ParseError parse_error(const std::shared_ptr<Alphabet>& a, std::string_view text) {
  try {
    parse_string(a, text, "world.txt");
  } catch (const ParseError& e) {
    return e;
  }
  ADD_FAILURE() << "no ParseError for: " << text;
  return ParseError("", 0, 0, "", "", "");
}
}  // namespace

TEST(Text, CanonicalStringsPrintBackUnchanged) {
  auto a = case_study_alphabet();
  for (const char* s : {
           "",
           "Robot<0>",
           "Move<0.5>(Robot<1>)",
           "Rotate<0.3>(Move<0.5>(Robot<1>)) . Robot<2>",
           "Move<1.0>(Robot<0> . Move<-2.5>(Robot<0> . Lamp) . Lamp<1, 2.0, true, \"x\">)",
           "ARobot<id=1, row=3, column=4, angle=0.0, objective=\"kitchen\">",
           "Lamp<\"quote \\\" backslash \\\\ newline \\n tab \\t\">",
       }) {
    EXPECT_EQ(canon(a, s), s);
  }
}

TEST(Text, NonCanonicalInputIsNormalised) {
  auto a = case_study_alphabet();
  // Defaults filled, ints widened to reals, keywords to positions, '·' and spacing normalised.
  EXPECT_EQ(canon(a, "Move<dist=1>( Robot )·Robot"), "Move<1.0>(Robot<0>) . Robot<0>");
  EXPECT_EQ(canon(a, "ARobot<row=3, column=4>  # a comment\n"),
            "ARobot<id=0, row=3, column=4, angle=0.0, objective=\"\">");
  EXPECT_EQ(canon(a, "  # only a comment\n  "), "");
  EXPECT_EQ(canon(a, "Lamp<+2, -0.0, 1e3, .5>"), "Lamp<2, -0.0, 1000.0, 0.5>");
}

TEST(Text, RealsPrintAsPythonRepr) {
  // Expected texts are Python's repr() of the same floats.
  const std::pair<double, const char*> cases[] = {
      {0.5, "0.5"},          {3.0, "3.0"},     {-0.0, "-0.0"},    {0.1, "0.1"},
      {1e16, "1e+16"},       {1e15, "1000000000000000.0"},       {1e-5, "1e-05"},
      {0.0001, "0.0001"},    {1.5e300, "1.5e+300"},              {123.456, "123.456"},
      {2.0 / 3.0, "0.6666666666666666"}, {5e-324, "5e-324"},     {1.7976931348623157e308, "1.7976931348623157e+308"},
      {-12345678.9, "-12345678.9"},       {1234567890123456.0, "1234567890123456.0"},
      {12345678901234567.0, "1.2345678901234568e+16"},
      // repr(float("nan")), repr(float("inf")), repr(float("-inf")): messages print them (they read
      // past the end of the text before).
      {std::nan(""), "nan"}, {HUGE_VAL, "inf"}, {-HUGE_VAL, "-inf"},
  };
  for (auto [value, text] : cases) EXPECT_EQ(format_real(value), text) << value;
}

TEST(Text, RealsRoundTripBitForBit) {
  Rng rng(3);
  auto a = case_study_alphabet();
  for (int i = 0; i < 2000; ++i) {
    std::uint64_t bits = rng.next_u64();
    double x;
    std::memcpy(&x, &bits, 8);
    if (!std::isfinite(x)) continue;
    const WorldString w = StringBuilder(a).open("Move", {x}).primitive("Lamp").close().finish();
    const WorldString back = parse_string(a, to_text(w));
    EXPECT_EQ(back, w) << to_text(w);
  }
}

TEST(Text, ErrorsNameLineColumnFoundAndExpected) {
  auto a = case_study_alphabet();
  {
    const ParseError e = parse_error(a, "Move<1>(Robot) .\n  Robt");
    EXPECT_EQ(e.source(), "world.txt");
    EXPECT_EQ(e.line(), 2u);
    EXPECT_EQ(e.column(), 3u);
    EXPECT_EQ(e.found(), "unknown symbol 'Robt'");
    EXPECT_NE(e.expected().find("did you mean 'Robot'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("world.txt:2:3"), std::string::npos) << e.what();
  }
  {
    const ParseError e = parse_error(a, "Move<1>(Robot");
    EXPECT_EQ(e.column(), 14u);
    EXPECT_EQ(e.found(), "end of text");
    EXPECT_NE(e.expected().find("')' to close the scope of 'Move' opened at line 1, column 1"), std::string::npos);
  }
  {
    const ParseError e = parse_error(a, "Move<1>()");
    EXPECT_EQ(e.column(), 9u);
    EXPECT_NE(e.expected().find("rule 5"), std::string::npos);
  }
  {
    const ParseError e = parse_error(a, "Move<\"far\">(Robot)");
    EXPECT_EQ(e.column(), 6u);
    EXPECT_EQ(e.expected(), "real for Move.dist");
    EXPECT_EQ(e.found(), "text \"far\"");
  }
  {
    const ParseError e = parse_error(a, "ARobot<row=1, colum=2>");
    EXPECT_EQ(e.column(), 21u);
    EXPECT_EQ(e.found(), "'colum'");
    EXPECT_NE(e.expected().find("id, row, column, angle, objective"), std::string::npos);
  }
  {
    const ParseError e = parse_error(a, "ARobot<row=1>");
    EXPECT_EQ(e.column(), 1u);
    EXPECT_NE(e.expected().find("attribute 'column' of 'ARobot' (it has no default)"), std::string::npos);
  }
  {
    const ParseError e = parse_error(a, "Robot(Robot)");
    EXPECT_EQ(e.column(), 6u);
    EXPECT_NE(e.expected().find("only transformations take a scope"), std::string::npos);
  }
  {
    const ParseError e = parse_error(a, "Robot . tick");
    EXPECT_NE(e.expected().find("'tick' is an event type"), std::string::npos);
  }
  {
    const ParseError e = parse_error(a, "Robot)");
    EXPECT_NE(e.expected().find("no scope is open"), std::string::npos);
  }
  {
    const ParseError e = parse_error(a, "Lamp<nan>");
    EXPECT_EQ(e.found(), "'nan'");
  }
  {
    const ParseError e = parse_error(a, "Lamp<1e999>");
    EXPECT_EQ(e.expected(), "a finite real number");
  }
  {
    const ParseError e = parse_error(a, "Lamp<\"open");
    EXPECT_NE(e.expected().find("to end the text that starts at line 1, column 6"), std::string::npos);
  }
  {  // Columns count characters: '·' is one column though two bytes.
    const ParseError e = parse_error(a, "Robot·Robt");
    EXPECT_EQ(e.column(), 7u);
  }
  {
    const ParseError e = parse_error(a, "Robot . ");
    EXPECT_EQ(e.found(), "end of text");
  }
  {
    const ParseError e = parse_error(a, "Lamp<99999999999999999999>");
    EXPECT_EQ(e.expected(), "an integer in the 64-bit range");
  }
}

// Rule 6, FIGURE → p+: primitives side by side are one figure, printed with a space between them
// and '.' between objects.
TEST(Text, FiguresOfPrimitivesSideBySidePrintBackUnchanged) {
  auto a = case_study_alphabet();
  for (const char* s : {
           "Robot<0> Lamp",
           "Robot<1> Robot<2> Lamp<3> . Robot<4>",
           "Move<0.5>(Robot<1> Lamp . Rotate<1.0>(Lamp Lamp)) . Lamp<2> Robot<0>",
           "ARobot<id=1, row=3, column=4, angle=0.0, objective=\"\"> . Robot<0> Robot<0>",
       }) {
    EXPECT_EQ(canon(a, s), s);
    const WorldString w = parse_string(a, s);
    EXPECT_EQ(parse_string(a, to_text(w)), w) << s;
    EXPECT_EQ(parse_string(a, to_text(w)).content_hash(), w.content_hash()) << s;
  }
  // Any white space or comment between the primitives; '.' and '·' still separate objects.
  EXPECT_EQ(canon(a, "Robot\n  Lamp  # a comment\n\tRobot<id=2>"), "Robot<0> Lamp Robot<2>");
  EXPECT_EQ(canon(a, "Robot<1>·Robot Lamp"), "Robot<1> . Robot<0> Lamp");
  // The figure's primitives are nodes of their own, the later ones joined to the one before.
  const WorldString w = parse_string(a, "Robot<1> Lamp Robot<2> . Robot<3>");
  ASSERT_EQ(w.nodes().size(), 4u);
  EXPECT_EQ(w.symbol_count(), 4u);
  const bool joined[] = {false, true, true, false};
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(w.nodes()[i].joined, joined[i]) << i;
  EXPECT_TRUE(w.node(1).joined());
  // A figure is not the same string as its primitives joined by '.', though φ runs them alike.
  const WorldString figure = parse_string(a, "Robot Lamp");
  const WorldString objects = parse_string(a, "Robot . Lamp");
  EXPECT_NE(figure, objects);
  EXPECT_NE(figure.content_hash(), objects.content_hash());
  EXPECT_EQ(sizeof(Node), 12u);
}

TEST(Text, OnlyPrimitivesAreJuxtaposedAndTheErrorNamesTheColumn) {
  auto a = case_study_alphabet();
  {
    const ParseError e = parse_error(a, "Robot ARobot<row=1, column=2>");
    EXPECT_EQ(e.line(), 1u);
    EXPECT_EQ(e.column(), 7u);
    EXPECT_EQ(e.found(), "'ARobot'");
    EXPECT_EQ(e.expected().rfind("'.' or end of text", 0), 0u) << e.expected();
    EXPECT_NE(e.expected().find("'ARobot' is an actor"), std::string::npos) << e.expected();
    EXPECT_NE(e.expected().find("rule 6"), std::string::npos) << e.expected();
  }
  {
    const ParseError e = parse_error(a, "ARobot<row=1, column=2> Robot");
    EXPECT_EQ(e.column(), 25u);
    EXPECT_EQ(e.found(), "'Robot'");
    EXPECT_NE(e.expected().find("an actor is followed by '.'"), std::string::npos) << e.expected();
  }
  {
    const ParseError e = parse_error(a, "Robot Move<1>(Robot)");
    EXPECT_EQ(e.column(), 7u);
    EXPECT_EQ(e.found(), "'Move'");
    EXPECT_NE(e.expected().find("'Move' is a transformation"), std::string::npos) << e.expected();
  }
  {
    const ParseError e = parse_error(a, "Move<1>(Robot) Robot");
    EXPECT_EQ(e.column(), 16u);
    EXPECT_NE(e.expected().find("a transformation's scope is followed by '.'"), std::string::npos) << e.expected();
  }
  {  // Inside a scope the alternative is ')'.
    const ParseError e = parse_error(a, "Move<1>(Robot\n   ARobot<row=1, column=2>)");
    EXPECT_EQ(e.line(), 2u);
    EXPECT_EQ(e.column(), 4u);
    EXPECT_EQ(e.expected().rfind("'.' or ')'", 0), 0u) << e.expected();
  }
  {  // The primitives of a figure are separated by white space.
    const ParseError e = parse_error(a, "Robot<1>Robot");
    EXPECT_EQ(e.column(), 9u);
    EXPECT_NE(e.expected().find("white space"), std::string::npos) << e.expected();
  }
  {  // An unknown name after a primitive is an unknown symbol, with its suggestion.
    const ParseError e = parse_error(a, "Robot Robt");
    EXPECT_EQ(e.column(), 7u);
    EXPECT_EQ(e.found(), "unknown symbol 'Robt'");
  }
}

TEST(WorldString, FiguresGoThroughTheBuilderAndItsCopies) {
  auto a = case_study_alphabet();
  StringBuilder b(a);
  b.primitive("Robot", {1}).juxtapose("Lamp").juxtapose("Robot", {2});
  EXPECT_EQ(to_text(b.finish()), "Robot<1> Lamp Robot<2>");
  // Only after a primitive.
  EXPECT_THROW(StringBuilder(a).juxtapose("Lamp"), SchemaError);
  EXPECT_THROW(StringBuilder(a).actor("ARobot", {0, 1, 2}).juxtapose("Lamp"), SchemaError);
  EXPECT_THROW(StringBuilder(a).open("Move", {1.0}).juxtapose("Lamp"), SchemaError);
  EXPECT_THROW(StringBuilder(a).primitive("Robot").juxtapose("Move", {1.0}), SchemaError);

  const WorldString src = parse_string(a, "Robot<1> Robot<2> . Lamp");
  auto copy = [&](const char* before, std::size_t begin, std::size_t end) {
    StringBuilder out(a);
    if (before[0] != '\0') out.append(parse_string(a, before));
    out.append_range(src, begin, end);
    const WorldString w = out.finish();
    EXPECT_EQ(parse_string(a, to_text(w)), w) << to_text(w);  // what is built prints and parses back
    return to_text(w);
  };
  EXPECT_EQ(copy("", 0, 3), "Robot<1> Robot<2> . Lamp");
  EXPECT_EQ(copy("Robot<9>", 0, 3), "Robot<9> . Robot<1> Robot<2> . Lamp");
  // A copy that starts at a figure's second primitive: joined to a primitive, else on its own.
  EXPECT_EQ(copy("Robot<9>", 1, 3), "Robot<9> Robot<2> . Lamp");
  EXPECT_EQ(copy("", 1, 3), "Robot<2> . Lamp");
  EXPECT_EQ(copy("ARobot<row=1, column=2>", 1, 2),
            "ARobot<id=0, row=1, column=2, angle=0.0, objective=\"\"> . Robot<2>");
  // One node at a time.
  StringBuilder n(a);
  for (std::size_t i = 0; i < 3; ++i) n.append_node(src, i);
  EXPECT_EQ(n.finish(), src);
  StringBuilder m(a);
  m.open("Move", {1.0}).append_node(src, 1).close();
  EXPECT_EQ(to_text(m.finish()), "Move<1.0>(Robot<2>)");
}

TEST(Text, DeepNestingParsesWithoutRecursion) {
  auto a = case_study_alphabet();
  std::string s;
  const int depth = 100000;
  for (int i = 0; i < depth; ++i) s += "Move<1.0>(";
  s += "Robot<0>";
  s += std::string(depth, ')');
  const WorldString w = parse_string(a, s);
  EXPECT_EQ(w.symbol_count(), static_cast<std::size_t>(depth + 1));
  EXPECT_EQ(to_text(w), s);
}

TEST(Text, BlobsAreReferencedByContentHash) {
  auto a = std::make_shared<Alphabet>();
  a->add_actor("Mapper", {}, Schema{{ParamSpec{"grid", ValueKind::Blob, std::nullopt}}, false}, nullptr);
  std::vector<std::int8_t> cells = {0, 100, -1, 0, 0, 100};
  auto grid = std::make_shared<const Blob>(DType::Int8, std::vector<std::int64_t>{2, 3}, cells.data(), cells.size());
  BlobTable table{{"g", grid}};
  const WorldString w = parse_string(a, "Mapper<grid=@g>", "<string>", &table);
  const std::string text = to_text(w);
  EXPECT_EQ(text, "Mapper<grid=" + blob_name(*grid) + ">");
  // The printed name resolves through a table keyed by the hash.
  BlobTable by_hash{{blob_name(*grid).substr(1), grid}};
  EXPECT_EQ(parse_string(a, text, "<string>", &by_hash), w);
  // A different content has a different name; an unknown name is a parse error.
  cells[0] = 100;
  const Blob other(DType::Int8, {2, 3}, cells.data(), cells.size());
  EXPECT_NE(blob_name(other), blob_name(*grid));
  EXPECT_THROW(parse_string(a, "Mapper<grid=@nothere>", "<string>", &table), ParseError);
  EXPECT_THROW(parse_string(a, "Mapper<grid=@g>"), ParseError);  // no table
}

// Blob names are xxHash's XXH3: its published value for the empty input (seed 0, xxHash's sanity
// test vectors), and every byte of a long input (XXH3's stripes of 64 bytes) counts.
TEST(Text, BlobHashesAreXxh3) {
  EXPECT_EQ(hash_bytes("", 0, 0), 0x2D06800538D394C2ULL);
  std::vector<unsigned char> bytes(100000, 7);
  const std::uint64_t whole = hash_bytes(bytes.data(), bytes.size());
  for (std::size_t at : {std::size_t{0}, std::size_t{63}, std::size_t{64}, std::size_t{50000}, bytes.size() - 1}) {
    bytes[at] ^= 1;
    EXPECT_NE(hash_bytes(bytes.data(), bytes.size()), whole) << "byte " << at;
    bytes[at] ^= 1;
  }
  EXPECT_EQ(hash_bytes(bytes.data(), bytes.size()), whole);
  EXPECT_NE(hash_bytes(bytes.data(), bytes.size(), 1), whole);  // the seed counts
}

TEST(Text, EventsParseAndPrint) {
  auto a = case_study_alphabet();
  EventList events(a);
  parse_event(events, "eLaser<to=2, dist=1.5, angle=0.25>");
  parse_event(events, "eLaser<3, 0.5>");
  parse_event(events, "tick");
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].target(), 2);
  EXPECT_EQ(to_text(events[0]), "eLaser<to=2, dist=1.5, angle=0.25>");
  EXPECT_EQ(to_text(events[1]), "eLaser<dist=3.0, angle=0.5>");
  EXPECT_EQ(to_text(events[2]), "tick");
  EXPECT_THROW(parse_event(events, "Robot"), ParseError);
  EXPECT_THROW(parse_event(events, "eLaser<dist=1.0>"), ParseError);  // angle has no default
  EXPECT_THROW(parse_event(events, "eLaser<to=1.5, dist=1, angle=1>"), ParseError);
}
