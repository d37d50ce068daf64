// Units inside expressions (vault-format.md, `expr`): a number written with a unit is that
// quantity, and the sides of + - and comparisons must have one dimension.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <random>

#include <fmt/format.h>

#include "core/expr.h"
#include "core/units.h"

namespace sscs {
namespace {

double eval(const std::string& text, std::vector<double> values = {},
            Expression::Literals literals = Expression::Literals::Si) {
  Expression::Error err;
  auto e = Expression::parse(text, &err, literals);
  EXPECT_TRUE(e) << text << ": " << err.message;
  if (!e) return NAN;
  EXPECT_EQ(e->names().size(), values.size()) << text;
  return e->evaluate(values.data());
}

/// The dimension check of `text` with names of the given dimensions (absent: plain).
Expression::Dimensions dims(const std::string& text, const std::map<std::string, Dim>& of = {}) {
  Expression::Error err;
  auto e = Expression::parse(text, &err);
  EXPECT_TRUE(e) << text << ": " << err.message;
  if (!e) return {};
  return e->check_dimensions([&](std::string_view n) -> std::optional<Dim> {
    auto it = of.find(std::string(n));
    if (it == of.end()) return std::nullopt;
    return it->second;
  });
}

TEST(ExprUnits, APlainNumberBesideAnAngleIsRadiansAndSaysSo) {
  // `yaw <= 10` is 10 rad by the spec, where a bound reads 10 deg: a warning at the number, for
  // every comparison and sum; none for 0, a number with a unit, or a number beside a length.
  const std::map<std::string, Dim> of = {{"yaw", Dim::Angle}, {"len", Dim::Length}};
  for (const char* op : {"<", "<=", ">", ">=", "==", "!=", "+", "-"}) {
    const Expression::Dimensions d = dims(fmt::format("yaw {} 10", op), of);
    ASSERT_TRUE(d.warning) << op;
    EXPECT_EQ(d.warning->position, fmt::format("yaw {} ", op).size()) << op;
    EXPECT_NE(d.warning->message.find("is 10 rad (572.958 deg)"), std::string::npos) << d.warning->message;
    EXPECT_TRUE(dims(fmt::format("0.5 {} yaw", op), of).warning) << op;
  }
  for (const char* clean : {"yaw <= 10 deg", "yaw >= 0", "len <= 10", "yaw * 2 <= 1 rad", "2 * len <= 3"})
    EXPECT_FALSE(dims(clean, of).warning) << clean;
}

TEST(ExprUnits, ANumberWithAUnitIsThatQuantityInSi) {
  EXPECT_DOUBLE_EQ(eval("turning_radius + 0.3 m", {1.2}), 1.5);
  EXPECT_DOUBLE_EQ(eval("yaw + 90 deg", {0}), std::numbers::pi / 2);
  EXPECT_EQ(eval("mass <= 2 t", {1999}), 1);
  EXPECT_EQ(eval("mass <= 2 t", {2001}), 0);
  EXPECT_DOUBLE_EQ(eval("1500 mm + 2 ft"), 1.5 + 0.6096);
  EXPECT_DOUBLE_EQ(eval("2 min + 1 h + 500 ms"), 120 + 3600 + 0.5);
  EXPECT_DOUBLE_EQ(eval("10 m/s * 2 s"), 20);
  EXPECT_DOUBLE_EQ(eval("90deg"), std::numbers::pi / 2);
  EXPECT_DOUBLE_EQ(eval("1e3 mm"), 1);
  EXPECT_DOUBLE_EQ(eval("-2 in"), -0.0508);
  EXPECT_DOUBLE_EQ(eval("50 %"), 0.5);
  EXPECT_DOUBLE_EQ(eval("20 lb"), 20 * 0.45359237);
}

TEST(ExprUnits, APowerOfAUnitBelongsToTheUnit) {
  EXPECT_DOUBLE_EQ(eval("2 m^2"), 2);
  EXPECT_DOUBLE_EQ(eval("(2 m)^2"), 4);
  EXPECT_DOUBLE_EQ(eval("3000 mm^2"), 3000e-6);
  EXPECT_EQ(dims("2 m^2").described, "a quantity in m^2");
  EXPECT_EQ(dims("(2 m)^2").described, "a quantity in m^2");
}

TEST(ExprUnits, FunctionsOfTheSameNameStayFunctions) {
  EXPECT_DOUBLE_EQ(eval("rad(90)"), std::numbers::pi / 2);
  EXPECT_DOUBLE_EQ(eval("min(1 m, 50 cm)"), 0.5);
  EXPECT_DOUBLE_EQ(eval("max(2 min, 100 s)"), 120);
  EXPECT_DOUBLE_EQ(eval("2 * rad(90)"), std::numbers::pi);
}

TEST(ExprUnits, SweepMetricsTakeLiteralsInFileUnits) {
  EXPECT_DOUBLE_EQ(eval("90 deg", {}, Expression::Literals::FileUnits), 90);
  EXPECT_NEAR(eval("1 rad", {}, Expression::Literals::FileUnits), 180 / std::numbers::pi, 1e-12);
  EXPECT_DOUBLE_EQ(eval("1500 mm", {}, Expression::Literals::FileUnits), 1.5);
  EXPECT_DOUBLE_EQ(eval("30 deg/s", {}, Expression::Literals::FileUnits), 30);
}

TEST(ExprUnits, SyntaxErrorsPointIntoTheTextAsWritten) {
  Expression::Error err;
  EXPECT_FALSE(Expression::parse("1500 mm + 2 ft +", &err));
  Expression::Error plain;  // the same error in a text of the same length without units
  EXPECT_FALSE(Expression::parse("1500000 + 22222 +", &plain));
  EXPECT_EQ(err.position, plain.position - 1) << err.message;
  EXPECT_FALSE(Expression::parse("1500 mm + 2 ft ) + 1", &err));
  EXPECT_EQ(err.position, 15u) << err.message;
  EXPECT_FALSE(Expression::parse("2 inch", &err));  // a word that only starts like a unit is none
  EXPECT_FALSE(Expression::parse("2 x", &err));
  EXPECT_EQ(err.position, 2u) << err.message;
}

TEST(ExprUnits, SidesOfAdditionsAndComparisonsMustHaveOneDimension) {
  const std::map<std::string, Dim> of = {{"width", Dim::Length}, {"yaw", Dim::Angle}, {"mass", Dim::Mass},
                                         {"n", Dim::None},       {"t", Dim::Time},    {"speed", Dim::Velocity}};
  auto d = dims("width + 0.3 kg", of);
  ASSERT_TRUE(d.error);
  EXPECT_EQ(d.error->position, 8u);
  EXPECT_EQ(d.error->message, "the two sides of '+' differ in dimension: 'width' is a length, '0.3 kg' is a mass");
  d = dims("yaw + 0.3 m", of);
  ASSERT_TRUE(d.error);
  EXPECT_EQ(d.error->position, 6u);
  d = dims("n <= 2 t", of);  // a count is no mass
  ASSERT_TRUE(d.error);
  EXPECT_EQ(d.error->message, "the two sides of '<=' differ in dimension: 'n' is a pure number, '2 t' is a mass");
  d = dims("width > 0 && (mass - 5 kg) / (1 kg) > 3 deg", of);
  ASSERT_TRUE(d.error);
  EXPECT_EQ(d.error->position, 38u);
  d = dims("width > 1 ? 2 m : 3 kg", of);
  ASSERT_TRUE(d.error);
  EXPECT_EQ(d.error->position, 18u);
  d = dims("min(width, 2 s)", of);
  ASSERT_TRUE(d.error);
  EXPECT_EQ(d.error->message, "the arguments of min() differ in dimension: 'width' is a length, '2 s' is a time");
  EXPECT_TRUE(dims("atan2(width, 2 kg)", of).error);
}

TEST(ExprUnits, PlainNumbersAndPlainNamesFitAnyDimension) {
  const std::map<std::string, Dim> of = {{"width", Dim::Length}, {"yaw", Dim::Angle}, {"t", Dim::Time}, {"speed", Dim::Velocity}};
  for (const char* ok : {"width - 0.5", "width + gap + 0.3 m", "yaw + rad(90)", "yaw + 90 deg", "2 * width <= 3 m",
                         "width / t <= speed", "width / 2 s <= 1 m/s", "sqrt(width^2 + 4 m^2) <= 5 m", "sin(yaw) * 2 m + width",
                         "(width > 1) + 1", "!(width < 2 m)", "atan2(width, 1 m) < 90 deg", "abs(width - 1 m) < 1 cm",
                         "deg(yaw) < 90", "width * width >= 1 m^2", "speed * t == width"}) {
    auto d = dims(ok, of);
    EXPECT_FALSE(d.error) << ok << ": " << d.error->message;
  }
  EXPECT_EQ(dims("width - 0.5", of).dim, Dim::Length);
  EXPECT_EQ(dims("width / t", of).dim, Dim::Velocity);
  EXPECT_EQ(dims("2 m / 4 s", of).described, "a velocity");
  EXPECT_EQ(dims("1 m / (width * t)", of).dim, Dim::Frequency);
  EXPECT_FALSE(dims("1 + 2", of).known);
  EXPECT_EQ(dims("width / (1 m)", of).dim, Dim::None);
  // A plain factor may carry a unit (`100 * stroke` kg from a length): its product fits anything.
  EXPECT_FALSE(dims("300 + 100 * (width + 1)", of).known);
  EXPECT_FALSE(dims("2 * width + 3 kg", of).error);
  EXPECT_EQ(dims("2 * width + 3 kg", of).dim, Dim::Mass);
  EXPECT_EQ(dims("width * 2 kg / t^2", of).described, "a quantity in m·kg/s^2");
}

// Every pair of units: `a U + b V` is refused exactly when U and V measure different things, and
// the value of a literal is its number times the unit's size, at random magnitudes.
TEST(ExprUnits, EveryPairOfUnits) {
  const std::vector<std::string> words = {"m", "mm", "cm", "km", "in", "ft", "yd", "deg", "rad", "kg", "g", "t",
                                          "lb", "s", "ms", "min", "h", "m/s", "mm/s", "deg/s", "rad/s", "Hz"};
  std::mt19937 rng(35);
  std::uniform_real_distribution<double> mag(-6, 6);
  for (const std::string& u : words) {
    auto unit = unit_word_at(u);
    ASSERT_TRUE(unit && unit->word == u) << u;
    for (int k = 0; k < 20; ++k) {
      const double x = std::pow(10.0, mag(rng));
      const std::string text = fmt::format("{:.17g} {}", x, u);
      EXPECT_NEAR(eval(text), x * unit->to_si, 1e-12 * x * unit->to_si) << text;
    }
    for (const std::string& v : words) {
      const std::string text = fmt::format("1 {} + 2 {}", u, v);
      const bool same = unit_word_at(v)->dim == unit->dim;
      EXPECT_EQ(!dims(text).error, same) << text;
      EXPECT_EQ(!dims(fmt::format("1 {} < 2 {}", u, v)).error, same) << text;
    }
  }
}

}  // namespace
}  // namespace sscs
