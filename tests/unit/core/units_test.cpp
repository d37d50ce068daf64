#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include <cmath>
#include <numbers>

#include "core/units.h"

namespace sscs {
namespace {

TEST(Units, PlainNumbersHaveNoDimension) {
  auto q = parse_quantity("1.5");
  ASSERT_TRUE(q);
  EXPECT_DOUBLE_EQ(q->si, 1.5);
  EXPECT_EQ(q->dim, Dim::None);
  EXPECT_FALSE(q->has_unit);
  EXPECT_DOUBLE_EQ(parse_quantity("-2e3")->si, -2000);
  EXPECT_DOUBLE_EQ(parse_quantity("+.5")->si, 0.5);
}

TEST(Units, LiteralsConvertToSi) {
  struct Case {
    const char* text;
    double si;
    Dim dim;
  } cases[] = {
      {"300 mm", 0.3, Dim::Length},       {"2 ft", 0.6096, Dim::Length},        {"1.5 in", 0.0381, Dim::Length},
      {"90 deg", std::numbers::pi / 2, Dim::Angle}, {"1.2 rad", 1.2, Dim::Angle}, {"500 ms", 0.5, Dim::Time},
      {"20 lb", 9.0718474, Dim::Mass},    {"2 t", 2000, Dim::Mass},              {"0.25 m/s", 0.25, Dim::Velocity},
      {"50%", 0.5, Dim::Fraction},        {"100 Hz", 100, Dim::Frequency},       {"-3cm", -0.03, Dim::Length},
      {"1e3 mm", 1.0, Dim::Length},
  };
  for (const Case& c : cases) {
    auto q = parse_quantity(c.text);
    ASSERT_TRUE(q) << c.text;
    EXPECT_NEAR(q->si, c.si, 1e-12) << c.text;
    EXPECT_EQ(q->dim, c.dim) << c.text;
    EXPECT_TRUE(q->has_unit) << c.text;
  }
}

TEST(Units, UnknownUnitIsNamed) {
  std::string unknown;
  EXPECT_FALSE(parse_quantity("10 furlong", &unknown));
  EXPECT_EQ(unknown, "furlong");
  unknown.clear();
  EXPECT_FALSE(parse_quantity("Room1.height - 2", &unknown));  // an expression, not a unit
  EXPECT_EQ(unknown, "");
  EXPECT_FALSE(parse_quantity("a + b", &unknown));
  EXPECT_EQ(unknown, "");
}

TEST(Units, NonFiniteNumbersAreRejected) {
  EXPECT_FALSE(parse_number("nan"));
  EXPECT_FALSE(parse_number("inf"));
  EXPECT_FALSE(parse_number("1e999"));
  EXPECT_EQ(nonfinite_number(".nan"), "it is not a finite number");
  EXPECT_EQ(nonfinite_number("-.inf"), "it is not a finite number");
  EXPECT_EQ(nonfinite_number("1e999"), "1e999 is beyond the range of numbers (about ±1.8e308)");
  EXPECT_EQ(nonfinite_number("-1e999 m"), "-1e999 is beyond the range of numbers (about ±1.8e308)");
  EXPECT_EQ(nonfinite_number("+1e999km"), "1e999 is beyond the range of numbers (about ±1.8e308)");
  EXPECT_EQ(nonfinite_number("1e-400 mm"),
            "1e-400 is too close to zero for a number (the smallest is about 2.2e-308); write 0 if that is meant");
  EXPECT_EQ(nonfinite_number("1e99"), "");
  EXPECT_EQ(nonfinite_number("1e99 m"), "");
  EXPECT_EQ(nonfinite_number("1e999 * x"), "");  // an expression: its evaluation says what is wrong
  EXPECT_EQ(nonfinite_number("banana"), "");
}

TEST(Units, FileUnitsAreDegreesForAngles) {
  EXPECT_STREQ(file_unit(Dim::Length), "m");
  EXPECT_STREQ(file_unit(Dim::Angle), "deg");
  EXPECT_NEAR(si_to_file(std::numbers::pi, Dim::Angle), 180.0, 1e-12);
  EXPECT_DOUBLE_EQ(si_to_file(2.5, Dim::Length), 2.5);
  EXPECT_EQ(known_units(Dim::Angle), "deg, rad");
}

}  // namespace
}  // namespace sscs

namespace sscs {
namespace {

// Property: stable() rounds to 12 significant digits exactly as printf("%.12g") + strtod, over
// random magnitudes and mantissas (reports and goldens rest on it).
TEST(UnitsProperty, StableIsPrintfTwelveDigits) {
  std::mt19937_64 rng(3);
  for (int i = 0; i < 200000; ++i) {
    double v = std::ldexp(std::uniform_real_distribution<double>(-1, 1)(rng), std::uniform_int_distribution<int>(-80, 80)(rng));
    if (i % 7 == 0) v = std::round(v * 1000) / 1000;
    if (i % 5 == 0) v = std::round(std::ldexp(v, -60) * 1e6) / 1e6;  // short decimals below 1e6
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.12g", v);
    double expected = std::strtod(buf, nullptr);
    if (expected == 0) expected = 0.0;
    ASSERT_EQ(stable(v), expected) << buf;
  }
}

}  // namespace
}  // namespace sscs
