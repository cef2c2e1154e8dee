#include <gtest/gtest.h>

#include "helpers.hpp"

using namespace vwg;
using namespace vwg::testing;

TEST(Alphabet, RegistersEachKindWithItsOwnId) {
  Alphabet a;
  const SymbolId robot = a.add_primitive("Robot");
  const SymbolId move = a.add_transformation("Move", schema({real("dist")}));
  const EventTypeId tick = a.add_event_type("tick", false);
  const EventTypeId show = a.add_event_type("show", true);
  const SymbolId blinker = a.add_actor("Blinker", {"tick", "show"}, schema({integer("on", 0)}), nullptr);
  EXPECT_EQ(a.symbol(robot).kind, SymbolKind::Primitive);
  EXPECT_EQ(a.symbol(move).kind, SymbolKind::Transformation);
  EXPECT_EQ(a.symbol(blinker).kind, SymbolKind::Actor);
  EXPECT_TRUE(a.symbol(blinker).responds.contains(tick));
  EXPECT_TRUE(a.symbol(blinker).responds.contains(show));
  EXPECT_FALSE(a.event_type(tick).visual);
  EXPECT_TRUE(a.event_type(show).visual);
  EXPECT_EQ(a.find_symbol("Move"), move);
  EXPECT_EQ(a.find_event_type("show"), show);
  EXPECT_FALSE(a.find_symbol("tick"));  // an event type is not a symbol
}

TEST(Alphabet, RefusesADuplicateNameAcrossKinds) {
  Alphabet a;
  a.add_primitive("Robot");
  EXPECT_THROW(a.add_primitive("Robot"), SchemaError);
  EXPECT_THROW(a.add_transformation("Robot"), SchemaError);
  EXPECT_THROW(a.add_event_type("Robot", false), SchemaError);
  try {
    a.add_event_type("Robot", false);
  } catch (const SchemaError& e) {
    EXPECT_NE(std::string(e.what()).find("already registered as a primitive"), std::string::npos) << e.what();
  }
}

TEST(Alphabet, RefusesBadNamesAndSchemas) {
  Alphabet a;
  EXPECT_THROW(a.add_primitive("2D"), SchemaError);
  EXPECT_THROW(a.add_primitive("true"), SchemaError);
  EXPECT_THROW(a.add_primitive("a-b"), SchemaError);
  EXPECT_THROW(a.add_primitive(""), SchemaError);
  EXPECT_THROW(a.add_transformation("T", schema({real("x"), real("x")})), SchemaError);
  EXPECT_THROW(a.add_event_type("e", false, schema({real("to")})), SchemaError);  // reserved
  EXPECT_THROW(a.add_actor("A", {"nope"}, {}, nullptr), SchemaError);  // unknown event type
  // A default of the wrong kind, and a non-finite default, are refused at registration.
  EXPECT_THROW(a.add_primitive("P", Schema{{ParamSpec{"x", ValueKind::Bool, Datum(1.5)}}, false}), SchemaError);
  EXPECT_THROW(a.add_primitive("Q", schema({real("x", std::nan(""))})), SchemaError);
}

TEST(Alphabet, IdAttributeIsFoundOnlyWhenItIsAnInteger) {
  Alphabet a;
  const auto r = a.add_actor("R", {}, schema({integer("id", 0), real("x", 0)}), nullptr);
  const auto s = a.add_actor("S", {}, schema({real("id", 0)}), nullptr);
  EXPECT_EQ(a.symbol(r).id_attribute, 0);
  EXPECT_EQ(a.symbol(s).id_attribute, -1);
}

TEST(Rng, SameSeedSameSequenceAndUniformInRange) {
  Rng a(42), b(42), c(43);
  bool differs = false;
  for (int i = 0; i < 1000; ++i) {
    const auto x = a.next_u64();
    EXPECT_EQ(x, b.next_u64());
    differs |= x != c.next_u64();
    const double u = a.uniform();
    b.uniform();
    c.uniform();
    EXPECT_GE(u, 0.0);
    EXPECT_LT(u, 1.0);
  }
  EXPECT_TRUE(differs);
  // The mean of 100k uniforms is 0.5 within 5 standard errors (sigma = sqrt(1/12/1e5) ~ 0.000913).
  Rng r(7);
  double sum = 0;
  for (int i = 0; i < 100000; ++i) sum += r.uniform();
  EXPECT_NEAR(sum / 100000, 0.5, 5 * 0.000913);
}
