#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

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

TEST(Rng, NormalFollowsTheStandardNormalAndRestartsWithItsSeed) {
  // 200,000 draws against the standard normal's own numbers: mean 0 and variance 1 within 5
  // standard errors (sqrt(1/n) and sqrt(2/n)), the share beyond 3 sigma (0.0027, from erfc)
  // within 5 of its standard errors, and Kolmogorov-Smirnov's distance to the CDF 0.5 erfc(-x/√2)
  // under its 0.1 % critical value, 1.95 / sqrt(n).
  constexpr int n = 200000;
  Rng r(11);
  std::vector<double> x(n);
  double sum = 0, squares = 0;
  int tails = 0;
  for (double& v : x) {
    v = r.normal();
    sum += v, squares += v * v, tails += std::abs(v) > 3.0;
  }
  const double mean = sum / n, variance = squares / n - mean * mean;
  EXPECT_NEAR(mean, 0.0, 5 * std::sqrt(1.0 / n));
  EXPECT_NEAR(variance, 1.0, 5 * std::sqrt(2.0 / n));
  const double beyond = std::erfc(3.0 / std::sqrt(2.0));  // 0.0026998
  EXPECT_NEAR(static_cast<double>(tails) / n, beyond, 5 * std::sqrt(beyond * (1 - beyond) / n));
  std::sort(x.begin(), x.end());
  double ks = 0;
  for (int i = 0; i < n; ++i) {
    const double cdf = 0.5 * std::erfc(-x[i] / std::sqrt(2.0));
    ks = std::max({ks, std::abs(cdf - static_cast<double>(i) / n), std::abs(cdf - static_cast<double>(i + 1) / n)});
  }
  EXPECT_LT(ks, 1.95 / std::sqrt(static_cast<double>(n)));
  // The same seed gives the same values, also after a reseed in the middle of a pair.
  Rng a(5), b(5);
  a.normal();
  a.reseed(5);
  for (int i = 0; i < 9; ++i) EXPECT_EQ(a.normal(), b.normal()) << i;
}
