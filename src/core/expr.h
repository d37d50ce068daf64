#pragma once
/// Expressions over named values ("Room1.height - 0.5", "a > b ? c : d"), evaluated by muparser.
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sscs {

/// A parsed expression. Names may contain '.', so references such as `Room1.height` are single
/// variables. Operators: + - * / ^, comparisons, && || !, ?:; functions min max abs sqrt sin cos tan
/// atan2 floor ceil, deg(x) (radians to degrees) and rad(x) (degrees to radians); constant pi.
/// Movable, not copyable (it owns a muparser instance bound to its own variable slots).
class Expression {
 public:
  struct Error {
    std::string message;
    size_t position = 0;  ///< 0-based offset into the text
  };

  /// Parses `text`; on failure fills `error` and returns nullopt.
  static std::optional<Expression> parse(std::string_view text, Error* error);

  Expression(Expression&&) noexcept;
  Expression& operator=(Expression&&) noexcept;
  ~Expression();

  /// The variable names it reads, sorted; evaluate() takes their values in this order.
  const std::vector<std::string>& names() const { return names_; }
  const std::string& text() const { return text_; }
  /// Evaluates with `values[i]` for `names()[i]`. May return inf or nan (e.g. 1/0): callers check.
  /// A value met on the way that is not finite (`1/0 > 0`, `min(x, 0/0)`) makes the result NaN if
  /// one was NaN, else infinite. Comparisons hold up to rounding (a few ulps of the largest
  /// magnitude met); only the taken branch of `?:` is evaluated (`x > 0 ? sqrt(x) : 0` guards).
  double evaluate(const double* values) const;

 private:
  Expression();
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<std::string> names_;
  std::string text_;
};

/// What a non-finite result of Expression::evaluate means, for messages: a value met on the way
/// (any branch of it that was evaluated) was infinite or not a number.
std::string nonfinite_reason(double result);

/// Splits a boolean expression at its top-level `||`, `&&` or comparison, so that a check can
/// report a margin: for `L < R` the margin is R - L; for `A && B` the smaller, for `A || B` the
/// larger, for `!(A)` minus A's. Returns nullopt where no margin is defined (a ternary, a bare value).
struct MarginTree {
  enum class Op { Or, And, Not, Lt, Le, Gt, Ge, Eq, Ne } op;
  std::string lhs;  ///< for comparisons: the two sides' text
  std::string rhs;
  std::vector<MarginTree> children;  ///< for Or/And; Not: one
};
std::optional<MarginTree> split_for_margin(std::string_view text);

}  // namespace sscs
