#include "core/expr.h"

#include <muParser.h>

#include <cmath>
#include <deque>
#include <algorithm>
#include <initializer_list>
#include <limits>
#include <numbers>

namespace sscs {

namespace {
// Functions see every value they are given: one that is not finite, or a result that is not
// (sqrt(-1), log(0), exp(1000)), marks the evaluation, which then yields NaN whatever the
// function made of it (muparser's min(x, NaN) is x, sign(NaN) is 0). A value that is no number
// is never a verdict (issue 18).
thread_local bool g_non_finite = false;
thread_local bool g_not_a_number = false;  // one of them was NaN (else only infinities)
// The largest magnitude this evaluation has met (its inputs, and every operand): the scale of the
// rounding a value computed from them may carry.
thread_local double g_scale = 0;
double checked(double result, std::initializer_list<double> args) {
  for (double a : args) {
    if (!std::isfinite(a)) g_non_finite = true;
    else g_scale = std::max(g_scale, std::abs(a));
    if (std::isnan(a)) g_not_a_number = true;
  }
  if (!std::isfinite(result)) g_non_finite = true;
  if (std::isnan(result)) g_not_a_number = true;
  return result;
}
/// Rounding two values compared may carry: a few ulps of the largest magnitude met so far.
double slack(double a, double b) {
  return 16 * std::numeric_limits<double>::epsilon() * std::max({std::abs(a), std::abs(b), g_scale});
}
double multi(const double* args, int n, double (*fold)(double, double), bool mean) {
  double r = args[0];
  bool bad = !std::isfinite(args[0]);
  for (int i = 1; i < n; ++i) {
    bad = bad || !std::isfinite(args[i]);
    r = fold(r, args[i]);
  }
  if (mean) r /= n;
  if (bad) {
    g_non_finite = true;
    for (int i = 0; i < n; ++i) g_not_a_number = g_not_a_number || std::isnan(args[i]);
  }
  return checked(r, {});
}
double fn_min(const double* a, int n) { return multi(a, n, [](double x, double y) { return std::min(x, y); }, false); }
double fn_max(const double* a, int n) { return multi(a, n, [](double x, double y) { return std::max(x, y); }, false); }
double fn_sum(const double* a, int n) { return multi(a, n, [](double x, double y) { return x + y; }, false); }
double fn_avg(const double* a, int n) { return multi(a, n, [](double x, double y) { return x + y; }, true); }
double op_not(double x) { return checked(x == 0 ? 1.0 : 0.0, {x}); }
double fn_atan2(double y, double x) { return checked(std::atan2(y, x), {y, x}); }
// muparser's built-in operators and functions, redefined so that they too mark a value that is
// not finite ((0/0 > 1) == 0 would otherwise compare 0 with 0; min(x, NaN) is x).
struct BinaryOp {
  const char* name;
  double (*f)(double, double);
  int precedence;
  mu::EOprtAssociativity associativity;
};
const BinaryOp kBinaryOps[] = {
    {"+", [](double a, double b) { return checked(a + b, {a, b}); }, mu::prADD_SUB, mu::oaLEFT},
    {"-", [](double a, double b) { return checked(a - b, {a, b}); }, mu::prADD_SUB, mu::oaLEFT},
    {"*", [](double a, double b) { return checked(a * b, {a, b}); }, mu::prMUL_DIV, mu::oaLEFT},
    {"/", [](double a, double b) { return checked(a / b, {a, b}); }, mu::prMUL_DIV, mu::oaLEFT},
    {"^", [](double a, double b) { return checked(std::pow(a, b), {a, b}); }, mu::prPOW, mu::oaRIGHT},
    // Comparisons anywhere in an expression (a ternary's condition, `(a == b) + 1`) hold up to
    // rounding, as a check's top-level comparison does: values equal up to rounding are equal.
    {"<", [](double a, double b) { return checked(b - a > slack(a, b), {a, b}); }, mu::prCMP, mu::oaLEFT},
    {">", [](double a, double b) { return checked(a - b > slack(a, b), {a, b}); }, mu::prCMP, mu::oaLEFT},
    {"<=", [](double a, double b) { return checked(a - b <= slack(a, b), {a, b}); }, mu::prCMP, mu::oaLEFT},
    {">=", [](double a, double b) { return checked(b - a <= slack(a, b), {a, b}); }, mu::prCMP, mu::oaLEFT},
    {"==", [](double a, double b) { return checked(std::abs(a - b) <= slack(a, b), {a, b}); }, mu::prCMP, mu::oaLEFT},
    {"!=", [](double a, double b) { return checked(std::abs(a - b) > slack(a, b), {a, b}); }, mu::prCMP, mu::oaLEFT},
    {"&&", [](double a, double b) { return checked(a != 0 && b != 0, {a, b}); }, mu::prLAND, mu::oaLEFT},
    {"||", [](double a, double b) { return checked(a != 0 || b != 0, {a, b}); }, mu::prLOR, mu::oaLEFT},
};
struct UnaryFunction {
  const char* name;
  double (*f)(double);
};
const UnaryFunction kUnaryFunctions[] = {
    {"sqrt", [](double x) { return checked(std::sqrt(x), {x}); }},   {"log", [](double x) { return checked(std::log(x), {x}); }},
    {"ln", [](double x) { return checked(std::log(x), {x}); }},      {"log2", [](double x) { return checked(std::log2(x), {x}); }},
    {"log10", [](double x) { return checked(std::log10(x), {x}); }}, {"exp", [](double x) { return checked(std::exp(x), {x}); }},
    {"asin", [](double x) { return checked(std::asin(x), {x}); }},   {"acos", [](double x) { return checked(std::acos(x), {x}); }},
    {"sin", [](double x) { return checked(std::sin(x), {x}); }},     {"cos", [](double x) { return checked(std::cos(x), {x}); }},
    {"tan", [](double x) { return checked(std::tan(x), {x}); }},     {"atan", [](double x) { return checked(std::atan(x), {x}); }},
    {"abs", [](double x) { return checked(std::abs(x), {x}); }},     {"rint", [](double x) { return checked(std::rint(x), {x}); }},
    {"sign", [](double x) { return checked(x > 0 ? 1.0 : x < 0 ? -1.0 : 0.0, {x}); }},
    {"floor", [](double x) { return checked(std::floor(x), {x}); }}, {"ceil", [](double x) { return checked(std::ceil(x), {x}); }},
    {"deg", [](double x) { return checked(x * 180.0 / std::numbers::pi, {x}); }},
    {"rad", [](double x) { return checked(x * std::numbers::pi / 180.0, {x}); }},
};

double* new_slot(const char*, void* user) {
  auto* slots = static_cast<std::deque<double>*>(user);
  slots->push_back(0.0);
  return &slots->back();
}
}  // namespace

struct Expression::Impl {
  mu::Parser parser;
  std::deque<double> slots;  // deque: pointers stay valid as it grows
  std::vector<double*> bound;  // slot of names_[i]
};

Expression::Expression() : impl_(std::make_unique<Impl>()) {}
Expression::Expression(Expression&&) noexcept = default;
Expression& Expression::operator=(Expression&&) noexcept = default;
Expression::~Expression() = default;

std::optional<Expression> Expression::parse(std::string_view text, Error* error) {
  Expression e;
  e.text_ = std::string(text);
  mu::Parser& p = e.impl_->parser;
  try {
    p.DefineNameChars("0123456789_abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ.");
    p.EnableBuiltInOprt(false);
    for (const BinaryOp& op : kBinaryOps) p.DefineOprt(op.name, op.f, op.precedence, op.associativity, false);
    p.DefineInfixOprt("!", op_not);
    // Not folded at parse time: sqrt(-1) must mark its evaluation like sqrt(x) of x = -1.
    for (const UnaryFunction& fn : kUnaryFunctions) p.DefineFun(fn.name, fn.f, false);
    p.DefineFun("atan2", fn_atan2, false);
    p.DefineFun("min", fn_min, false);
    p.DefineFun("max", fn_max, false);
    p.DefineFun("sum", fn_sum, false);
    p.DefineFun("avg", fn_avg, false);
    p.DefineConst("pi", std::numbers::pi);
    p.SetVarFactory(new_slot, &e.impl_->slots);
    p.SetExpr(e.text_);
    // GetUsedVar parses the whole expression, so syntax errors surface here.
    const mu::varmap_type& used = p.GetUsedVar();
    for (const auto& [name, ptr] : used) {  // std::map: sorted by name
      e.names_.push_back(name);
      e.impl_->bound.push_back(ptr);
    }
    p.Eval();  // compile to bytecode now; values are all 0 so the result is ignored
  } catch (const mu::Parser::exception_type& ex) {
    if (error) {
      error->message = ex.GetMsg();
      error->position = static_cast<size_t>(std::max(0, ex.GetPos()));
    }
    return std::nullopt;
  }
  return e;
}

double Expression::evaluate(const double* values) const {
  for (size_t i = 0; i < impl_->bound.size(); ++i) *impl_->bound[i] = values[i];
  try {
    g_non_finite = g_not_a_number = false;
    g_scale = 0;
    for (size_t i = 0; i < impl_->bound.size(); ++i)
      if (std::isfinite(values[i])) g_scale = std::max(g_scale, std::abs(values[i]));
    double v = impl_->parser.Eval();
    // A value met on the way that is not finite makes the result so: NaN if one was NaN, else
    // infinite (`1/0 > 0` is "infinite", not "not a number"); inf stays where it is the result.
    if (g_non_finite && std::isfinite(v)) return g_not_a_number ? std::nan("") : INFINITY;
    return v;
  } catch (const mu::Parser::exception_type&) {
    return std::nan("");
  }
}

// ---- margin splitting ----------------------------------------------------------------------

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  return s;
}

/// Positions of a top-level (depth-0) occurrence of one of `ops`; "" when there is none.
struct Hit {
  size_t pos = std::string_view::npos;
  std::string_view op;
};

Hit find_top(std::string_view s, std::initializer_list<std::string_view> ops) {
  int depth = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    char c = s[i];
    if (c == '(') ++depth;
    else if (c == ')') --depth;
    else if (depth == 0) {
      for (std::string_view op : ops) {
        if (s.substr(i, op.size()) == op) {
          // "<" must not be the start of "<=", nor "=" the tail of "<=", ">=", "!=", "==".
          if ((op == "<" || op == ">") && i + 1 < s.size() && s[i + 1] == '=') continue;
          return {i, op};
        }
      }
    }
  }
  return {};
}

bool has_top(std::string_view s, char c) {
  int depth = 0;
  for (char x : s) {
    if (x == '(') ++depth;
    else if (x == ')') --depth;
    else if (depth == 0 && x == c) return true;
  }
  return false;
}

}  // namespace

std::optional<MarginTree> split_for_margin(std::string_view text) {
  text = trim(text);
  // Strip one pair of enclosing parentheses: "(a < b)".
  while (text.size() >= 2 && text.front() == '(' && text.back() == ')') {
    int depth = 0;
    bool encloses = true;
    for (size_t i = 0; i + 1 < text.size(); ++i) {
      if (text[i] == '(') ++depth;
      else if (text[i] == ')') --depth;
      if (depth == 0) {
        encloses = false;
        break;
      }
    }
    if (!encloses) break;
    text = trim(text.substr(1, text.size() - 2));
  }
  if (has_top(text, '?')) return std::nullopt;
  for (auto [token, op] : {std::pair{"||", MarginTree::Op::Or}, std::pair{"&&", MarginTree::Op::And}}) {
    Hit h = find_top(text, {token});
    if (h.pos == std::string_view::npos) continue;
    auto left = split_for_margin(text.substr(0, h.pos));
    auto right = split_for_margin(text.substr(h.pos + 2));
    if (!left || !right) return std::nullopt;
    MarginTree t{op, "", "", {}};
    // Flatten chains of the same operator.
    for (auto* side : {&*left, &*right}) {
      if (side->op == op) {
        for (auto& c : side->children) t.children.push_back(std::move(c));
      } else {
        t.children.push_back(std::move(*side));
      }
    }
    return t;
  }
  // `!(A)`: the negation of one parenthesised group (`!a == b` is `(!a) == b`: no margin).
  if (text.size() > 2 && text.front() == '!' && text[1] != '=') {
    std::string_view rest = trim(text.substr(1));
    if (rest.empty() || rest.front() != '(' || rest.back() != ')') return std::nullopt;
    int depth = 0;
    for (size_t i = 0; i + 1 < rest.size(); ++i) {
      if (rest[i] == '(') ++depth;
      else if (rest[i] == ')') --depth;
      if (depth == 0) return std::nullopt;  // "!(a) < (b)": the group ends before the text does
    }
    auto child = split_for_margin(rest);
    if (!child) return std::nullopt;
    MarginTree t{MarginTree::Op::Not, "", "", {}};
    t.children.push_back(std::move(*child));
    return t;
  }
  Hit h = find_top(text, {"<=", ">=", "==", "!=", "<", ">"});
  if (h.pos == std::string_view::npos) return std::nullopt;
  std::string_view lhs = trim(text.substr(0, h.pos));
  std::string_view rhs = trim(text.substr(h.pos + h.op.size()));
  // A second comparison at the same level ("a < b < c") has no single margin.
  if (find_top(rhs, {"<=", ">=", "==", "!=", "<", ">"}).pos != std::string_view::npos) return std::nullopt;
  if (lhs.empty() || rhs.empty() || lhs.front() == '!') return std::nullopt;
  MarginTree::Op op = h.op == "<=" ? MarginTree::Op::Le
                      : h.op == ">=" ? MarginTree::Op::Ge
                      : h.op == "==" ? MarginTree::Op::Eq
                      : h.op == "!=" ? MarginTree::Op::Ne
                      : h.op == "<"  ? MarginTree::Op::Lt
                                     : MarginTree::Op::Gt;
  return MarginTree{op, std::string(lhs), std::string(rhs), {}};
}

std::string nonfinite_reason(double result) {
  return std::isnan(result) ? "a value in it is not a number (0/0, the square root of a negative, ...)"
                            : "a value in it is infinite (a division by zero, an overflow, ...)";
}

}  // namespace sscs
