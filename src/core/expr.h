#pragma once
/// Expressions over named values ("Room1.height - 0.5", "a > b ? c : d", "yaw + 90 deg"),
/// evaluated by muparser, with a dimension check of what they add and compare.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/units.h"

namespace sscs {

/// A parsed expression. Names may contain '.', so references such as `Room1.height` are single
/// variables. Operators: + - * / ^, comparisons, && || !, ?:; functions min max abs sqrt sin cos tan
/// atan2 floor ceil, deg(x) (radians to degrees) and rad(x) (degrees to radians); constant pi.
/// A number followed by a unit (`0.3 m`, `90 deg`, `2 t`, `1.5 m/s`) is that quantity in SI (or,
/// with Literals::FileUnits, in the file unit of its dimension: what sweep metrics compute in).
/// Movable, not copyable (it owns a muparser instance bound to its own variable slots).
/// Where an offset of a rewritten text lies in the text as written, for error carets: the
/// rewrite records (offset in the rewritten text, offset as written) after each replacement.
struct OffsetMap {
  std::vector<std::pair<size_t, size_t>> anchors;
  size_t original(size_t pos) const {
    size_t rewritten = 0, written = 0;
    for (const auto& [r, w] : anchors) {
      if (r > pos) break;
      rewritten = r;
      written = w;
    }
    return written + (pos - rewritten);
  }
};

class Expression {
 public:
  struct Error {
    std::string message;
    size_t position = 0;  ///< 0-based offset into the text
  };
  enum class Literals : uint8_t { Si, FileUnits };

  /// Parses `text`; on failure fills `error` and returns nullopt.
  static std::optional<Expression> parse(std::string_view text, Error* error, Literals literals = Literals::Si);

  /// The dimension of a name the expression reads: nullopt for one that takes the dimension of
  /// what it meets, as a plain number does (a parameter written without a unit); Dim::None for a
  /// count or another pure number.
  using DimOf = std::function<std::optional<Dim>(std::string_view name)>;
  /// What the dimension check found.
  struct Dimensions {
    std::optional<Error> error;  ///< the first mismatch, at the token that does not fit
    /// A plain number beside an angle (`yaw <= 10`): radians, as the spec says, but likely meant
    /// as degrees (a `bound` reads the same 10 as 10 deg); at the number.
    std::optional<Error> warning;
    bool known = false;          ///< the result has a dimension (it is not a plain number)
    std::optional<Dim> dim;      ///< the result's dimension, when it is one sscs names
    std::string described;       ///< "a length", "a quantity in m^2": for messages
  };
  /// Checks that the sides of `+ - < <= == != >= >` and `?:`, and the arguments of min, max,
  /// sum, avg and atan2, have one dimension; a plain number fits any. Products and quotients
  /// combine dimensions (m / s is a velocity). A mismatch is an error at the token that does not fit.
  /// `excerpt(begin, end)` quotes a span of text() in messages (for a text rewritten before it
  /// was parsed: the span as written); by default the span itself.
  using Excerpt = std::function<std::string(size_t begin, size_t end)>;
  Dimensions check_dimensions(const DimOf& dim_of, const Excerpt& excerpt = {}) const;

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
