#include <gtest/gtest.h>

#include <cmath>

#include "core/expr.h"

namespace sscs {
namespace {

double eval(const char* text, std::vector<double> values = {}) {
  Expression::Error err;
  auto e = Expression::parse(text, &err);
  EXPECT_TRUE(e) << text << ": " << err.message;
  if (!e) return NAN;
  EXPECT_EQ(e->names().size(), values.size()) << text;
  return e->evaluate(values.data());
}

TEST(Expr, ReferencesAreSingleNamesSortedAlphabetically) {
  Expression::Error err;
  auto e = Expression::parse("Room1.height > 15 ? Door1.height == 7 : Door1.height < 7", &err);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->names(), (std::vector<std::string>{"Door1.height", "Room1.height"}));
  double v[] = {7, 20};
  EXPECT_EQ(e->evaluate(v), 1.0);
  double w[] = {7, 10};
  EXPECT_EQ(e->evaluate(w), 0.0);
}

TEST(Expr, OperatorsAndFunctions) {
  EXPECT_DOUBLE_EQ(eval("2^3 + 1"), 9);
  EXPECT_DOUBLE_EQ(eval("min(3, 1, 2) + max(4, 5)"), 6);
  EXPECT_DOUBLE_EQ(eval("abs(-2) * sqrt(16)"), 8);
  EXPECT_DOUBLE_EQ(eval("floor(1.7) + ceil(1.2)"), 3);
  EXPECT_NEAR(eval("atan2(1, 1)"), M_PI / 4, 1e-12);
  EXPECT_NEAR(eval("deg(pi)"), 180, 1e-12);
  EXPECT_NEAR(eval("rad(90)"), M_PI / 2, 1e-12);
  EXPECT_NEAR(eval("sin(rad(30)) + cos(0) + tan(0)"), 1.5, 1e-12);
  EXPECT_EQ(eval("!(1 > 2) && 1"), 1);
  EXPECT_EQ(eval("!1 || 0"), 0);
  EXPECT_EQ(eval("1 != 2"), 1);
  EXPECT_EQ(eval("a.b >= 2", {2}), 1);
}

TEST(Expr, SyntaxErrorsGivePositions) {
  Expression::Error err;
  EXPECT_FALSE(Expression::parse("1 + (2", &err));
  EXPECT_FALSE(err.message.empty());
  EXPECT_FALSE(Expression::parse("Room1.height <", &err));
  EXPECT_GE(err.position, 13u);  // at or just past the end
  EXPECT_LE(err.position, 15u);
}

TEST(Expr, DivisionByZeroIsNotFinite) { EXPECT_FALSE(std::isfinite(eval("1 / 0"))); }

TEST(Expr, MarginSplitsComparisonsAndLogic) {
  auto t = split_for_margin("a.x + 1 <= b.y");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->op, MarginTree::Op::Le);
  EXPECT_EQ(t->lhs, "a.x + 1");
  EXPECT_EQ(t->rhs, "b.y");
  t = split_for_margin("(a < b) && c > d && (e == f || g != h)");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->op, MarginTree::Op::And);
  ASSERT_EQ(t->children.size(), 3u);
  EXPECT_EQ(t->children[1].op, MarginTree::Op::Gt);
  EXPECT_EQ(t->children[2].op, MarginTree::Op::Or);
  EXPECT_FALSE(split_for_margin("a > 1 ? b < 2 : c < 3"));
  EXPECT_FALSE(split_for_margin("a + b"));
  EXPECT_FALSE(split_for_margin("a < b < c"));
  t = split_for_margin("min(a, b) >= 2");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->lhs, "min(a, b)");
}

}  // namespace
}  // namespace sscs
