#include "core/expr.h"
#include "core/names.h"

#include <muParser.h>

#include <cmath>
#include <deque>
#include <algorithm>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <string>

#include <fmt/format.h>

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

// ---- tokens: unit literals and the dimension check -----------------------------------------

namespace {

bool name_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool name_char(char c) { return name_start(c) || (c >= '0' && c <= '9') || c == '.'; }
bool digit(char c) { return c >= '0' && c <= '9'; }

struct Token {
  enum class Kind : uint8_t { Number, Name, Op, Open, Close, Comma, Question, Colon, Other } kind = Kind::Other;
  size_t pos = 0, len = 0;  // in the text as written
  double value = 0;         // Number: as written, without its unit
  std::optional<UnitWord> unit;
  int power = 1;            // of the unit: 2 m^2
  DimExponents dims() const {
    DimExponents e = exponents(unit->dim);
    for (int8_t& x : e) x = static_cast<int8_t>(x * power);
    return e;
  }
  /// The value in SI, or in file units: the unit to its power.
  double converted(Expression::Literals literals) const {
    double one = std::pow(unit->to_si, power);
    if (literals == Expression::Literals::FileUnits) one /= std::pow(file_unit_to_si(unit->dim), power);
    return value * one;
  }
};

/// The tokens of an expression as written. A number may carry a unit word after it (`0.3 m`,
/// `90deg`): a word sscs knows, not followed by a name's character or a call's '('.
std::vector<Token> tokenize(std::string_view s) {
  std::vector<Token> out;
  size_t i = 0;
  while (i < s.size()) {
    const char c = s[i];
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
      ++i;
      continue;
    }
    Token t;
    t.pos = i;
    if (digit(c) || (c == '.' && i + 1 < s.size() && digit(s[i + 1]))) {
      size_t j = i;
      while (j < s.size() && (digit(s[j]) || s[j] == '.')) ++j;
      if (j < s.size() && (s[j] == 'e' || s[j] == 'E')) {
        size_t k = j + 1;
        if (k < s.size() && (s[k] == '+' || s[k] == '-')) ++k;
        if (k < s.size() && digit(s[k])) {
          j = k;
          while (j < s.size() && digit(s[j])) ++j;
        }
      }
      t.kind = Token::Kind::Number;
      t.value = std::strtod(std::string(s.substr(i, j - i)).c_str(), nullptr);
      size_t k = j;
      while (k < s.size() && (s[k] == ' ' || s[k] == '\t')) ++k;
      if (auto u = unit_word_at(s.substr(k))) {
        size_t end = k + u->word.size();
        bool whole = end >= s.size() || !(name_char(s[end]) || s[end] == '(');
        // "%" needs no blank; a word does not run into the number's name ("2x" is no unit "x").
        if (whole) {
          t.unit = u;
          j = end;
          // A power of the unit belongs to it: `2 m^2` is two square metres, not (2 m)^2.
          size_t p = end;
          if (p < s.size() && s[p] == '^') {
            ++p;
            bool minus = p < s.size() && s[p] == '-';
            if (minus) ++p;
            size_t q = p;
            while (q < s.size() && digit(s[q])) ++q;
            if (q > p && q - p < 3 && (q >= s.size() || !name_char(s[q]))) {
              t.power = std::stoi(std::string(s.substr(p, q - p))) * (minus ? -1 : 1);
              j = q;
            }
          }
        }
      }
      t.len = j - i;
      i = j;
    } else if (name_start(c)) {
      size_t j = i;
      while (j < s.size() && name_char(s[j])) ++j;
      t.kind = Token::Kind::Name;
      t.len = j - i;
      i = j;
    } else {
      static constexpr std::string_view kOps[] = {"&&", "||", "<=", ">=", "==", "!=", "<", ">", "+", "-", "*", "/", "^", "!"};
      t.len = 1;
      t.kind = c == '(' ? Token::Kind::Open : c == ')' ? Token::Kind::Close : c == ',' ? Token::Kind::Comma
               : c == '?' ? Token::Kind::Question : c == ':' ? Token::Kind::Colon : Token::Kind::Other;
      if (t.kind == Token::Kind::Other)
        for (std::string_view op : kOps)
          if (s.substr(i).starts_with(op)) {
            t.kind = Token::Kind::Op;
            t.len = op.size();
            break;
          }
      i += t.len;
    }
    out.push_back(t);
  }
  return out;
}

/// The text muparser reads: each number with a unit replaced by its value (SI or file units),
/// and where each replacement ends in both texts, to map error positions back.
struct Internal {
  std::string text;
  OffsetMap written;  // after each literal
};

Internal with_literals_converted(std::string_view s, Expression::Literals literals) {
  Internal out;
  size_t copied = 0;
  for (const Token& t : tokenize(s)) {
    if (t.kind != Token::Kind::Number || !t.unit) continue;
    out.text.append(s.substr(copied, t.pos - copied));
    // Parenthesised: `-2 m^2`'s sign applies to the whole quantity, whatever follows.
    out.text += fmt::format("({:.17g})", t.converted(literals));
    copied = t.pos + t.len;
    out.written.anchors.emplace_back(out.text.size(), copied);
  }
  out.text.append(s.substr(copied));
  return out;
}

/// The dimension of a sub-expression: plain (a number without a unit, which fits any), known
/// (its exponents), or unknown (what the check cannot follow: a product with a plain number,
/// which may carry any unit, a power of a variable). Plain and unknown fit any dimension.
struct Dimension {
  enum class Kind : uint8_t { Plain, Known, Unknown } kind = Kind::Plain;
  DimExponents e{0, 0, 0, 0};
  size_t begin = 0, end = 0;  // its text as written

  static Dimension known(DimExponents e) { return {Kind::Known, e}; }
  static Dimension of(Dim d) { return known(exponents(d)); }
};

std::string describe(const Dimension& d) {
  if (d.kind != Dimension::Kind::Known) return "a plain number";
  if (auto named = dim_with(d.e)) return *named == Dim::None ? "a pure number" : a_dim(*named);
  static constexpr const char* kBase[] = {"m", "kg", "s", "rad"};
  std::string up, down;
  for (int k = 0; k < 4; ++k) {
    if (d.e[k] == 0) continue;
    std::string& part = d.e[k] > 0 ? up : down;
    if (!part.empty()) part += "·";
    part += kBase[k];
    if (std::abs(d.e[k]) != 1) part += fmt::format("^{}", std::abs(d.e[k]));
  }
  return fmt::format("a quantity in {}{}{}", up.empty() ? "1" : up, down.empty() ? "" : "/", down);
}

/// A recursive-descent reading of the tokens, with muparser's precedences (?:, ||, &&,
/// comparisons, + -, * /, unary - + !, ^), that computes dimensions. It reads only text muparser
/// accepted; what it does not follow gives up quietly (no dimension error).
class DimensionReader {
 public:
  DimensionReader(std::string_view text, const std::vector<Token>& tokens, const Expression::DimOf& dim_of,
                  const Expression::Excerpt& excerpt)
      : text_(text), t_(tokens), dim_of_(dim_of), excerpt_(excerpt) {}

  Expression::Dimensions read() {
    Expression::Dimensions out;
    try {
      Dimension d = ternary();
      if (i_ != t_.size()) return out;  // not followed to the end: no verdict
      out.warning = warning_;
      if (error_) {
        out.error = error_;
        return out;
      }
      out.known = d.kind == Dimension::Kind::Known;
      if (out.known) out.dim = dim_with(d.e);
      out.described = describe(d);
    } catch (const GiveUp&) {
      out.error = error_;
    }
    return out;
  }

 private:
  struct GiveUp {};
  std::string_view text_;
  const std::vector<Token>& t_;
  const Expression::DimOf& dim_of_;
  const Expression::Excerpt& excerpt_;
  size_t i_ = 0;
  std::optional<Expression::Error> error_, warning_;

  const Token* peek() const { return i_ < t_.size() ? &t_[i_] : nullptr; }
  bool at(Token::Kind k, std::string_view op = {}) const {
    const Token* t = peek();
    return t && t->kind == k && (op.empty() || text_.substr(t->pos, t->len) == op);
  }
  const Token& take() {
    if (i_ >= t_.size()) throw GiveUp{};
    return t_[i_++];
  }
  std::string written(const Dimension& d) const {
    if (excerpt_) return excerpt_(d.begin, d.end);
    return std::string(text_.substr(d.begin, d.end - d.begin));
  }

  /// The sides of `op` must agree: the result is the known one (either, when they agree).
  Dimension same(const Dimension& a, const Dimension& b, std::string_view what) {
    Dimension r = a.kind == Dimension::Kind::Known ? a : b.kind == Dimension::Kind::Known ? b
                  : a.kind == Dimension::Kind::Unknown ? a : b;
    if (a.kind == Dimension::Kind::Known && b.kind == Dimension::Kind::Known && a.e != b.e && !error_)
      error_ = Expression::Error{fmt::format("{} differ in dimension: '{}' is {}, '{}' is {}", what, written(a), describe(a),
                                             written(b), describe(b)),
                                 b.begin};
    // A number without a unit beside an angle is radians: say so once, it is rarely meant.
    for (const auto& [number, angle] : {std::pair{&a, &b}, std::pair{&b, &a}})
      if (number->kind == Dimension::Kind::Plain && angle->kind == Dimension::Kind::Known && angle->e == exponents(Dim::Angle) &&
          !warning_)
        if (auto x = parse_number(text_.substr(number->begin, number->end - number->begin)); x && *x != 0)
          warning_ = Expression::Error{fmt::format("'{}' beside the angle '{}' is {} rad ({:g} deg) inside an expression; write '{} deg' "
                                                   "if degrees are meant", written(*number), written(*angle), written(*number),
                                                   *x * 180 / std::numbers::pi, written(*number)),
                                       number->begin};
    r.begin = a.begin;
    r.end = b.end;
    return r;
  }
  static Dimension plain(size_t begin, size_t end) { return {Dimension::Kind::Plain, {0, 0, 0, 0}, begin, end}; }

  Dimension ternary() {
    Dimension c = binary(0);
    if (!at(Token::Kind::Question)) return c;
    take();
    Dimension a = ternary();
    if (!at(Token::Kind::Colon)) throw GiveUp{};
    take();
    Dimension b = ternary();
    Dimension r = same(a, b, "the two branches of '?:'");
    r.begin = c.begin;
    return r;
  }

  // Levels: 0 ||, 1 &&, 2 comparisons, 3 + -, 4 * /.
  Dimension binary(int level) {
    static const std::vector<std::vector<std::string_view>> kLevels = {
        {"||"}, {"&&"}, {"<", ">", "<=", ">=", "==", "!="}, {"+", "-"}, {"*", "/"}};
    if (level == 5) return unary();
    Dimension lhs = binary(level + 1);
    for (;;) {
      const Token* t = peek();
      if (!t || t->kind != Token::Kind::Op) return lhs;
      std::string_view op = text_.substr(t->pos, t->len);
      if (std::find(kLevels[level].begin(), kLevels[level].end(), op) == kLevels[level].end()) return lhs;
      take();
      Dimension rhs = binary(level + 1);
      if (level <= 1) {
        lhs = plain(lhs.begin, rhs.end);  // a truth value
      } else if (level == 2) {
        same(lhs, rhs, fmt::format("the two sides of '{}'", op));
        lhs = plain(lhs.begin, rhs.end);
      } else if (level == 3) {
        lhs = same(lhs, rhs, fmt::format("the two sides of '{}'", op));
      } else {
        lhs = product(lhs, rhs, op == "*" ? 1 : -1);
      }
    }
  }

  static Dimension product(const Dimension& a, const Dimension& b, int sign) {
    Dimension r;
    r.begin = a.begin;
    r.end = b.end;
    if (a.kind == Dimension::Kind::Unknown || b.kind == Dimension::Kind::Unknown) {
      r.kind = Dimension::Kind::Unknown;
      return r;
    }
    if (a.kind == Dimension::Kind::Plain && b.kind == Dimension::Kind::Plain) return r;
    // A plain factor may carry any unit (the library's `300 + 100 * (stroke + 1)` is kg and
    // kg/m): its product is of no dimension the check can know.
    if (a.kind == Dimension::Kind::Plain || b.kind == Dimension::Kind::Plain) {
      r.kind = Dimension::Kind::Unknown;
      return r;
    }
    r.kind = Dimension::Kind::Known;
    for (int k = 0; k < 4; ++k) r.e[k] = static_cast<int8_t>(a.e[k] + sign * b.e[k]);
    return r;
  }

  Dimension unary() {
    if (at(Token::Kind::Op, "-") || at(Token::Kind::Op, "+") || at(Token::Kind::Op, "!")) {
      const Token& t = take();
      bool negation = text_.substr(t.pos, t.len) == "!";
      Dimension d = unary();
      if (negation) d = plain(d.begin, d.end);
      d.begin = t.pos;
      return d;
    }
    return power();
  }

  Dimension power() {
    Dimension base = primary();
    if (!at(Token::Kind::Op, "^")) return base;
    take();
    const size_t exponent_at = i_;
    Dimension exponent = unary();
    Dimension r = base;
    r.end = exponent.end;
    if (base.kind != Dimension::Kind::Known || base.e == DimExponents{0, 0, 0, 0}) return r;
    // A known dimension to a whole power written as a number: m^2. Anything else is not followed.
    const Token& e = t_[exponent_at];
    if (i_ == exponent_at + 1 && e.kind == Token::Kind::Number && !e.unit && e.value == std::floor(e.value) && std::abs(e.value) < 8) {
      for (int k = 0; k < 4; ++k) r.e[k] = static_cast<int8_t>(r.e[k] * static_cast<int>(e.value));
      return r;
    }
    r.kind = Dimension::Kind::Unknown;
    return r;
  }

  Dimension primary() {
    const Token& t = take();
    Dimension d;
    d.begin = t.pos;
    d.end = t.pos + t.len;
    switch (t.kind) {
      case Token::Kind::Number:
        if (t.unit) {
          d.kind = Dimension::Kind::Known;
          d.e = t.dims();
        }
        return d;
      case Token::Kind::Open: {
        Dimension inner = ternary();
        if (!at(Token::Kind::Close)) throw GiveUp{};
        d.kind = inner.kind;
        d.e = inner.e;
        d.end = take().pos + 1;
        return d;
      }
      case Token::Kind::Name: {
        std::string_view name = text_.substr(t.pos, t.len);
        if (at(Token::Kind::Open)) return call(name, d);
        if (name == "pi") return d;
        if (auto dim = dim_of_(name)) {
          d.kind = Dimension::Kind::Known;
          d.e = exponents(*dim);
        }
        return d;
      }
      default: throw GiveUp{};
    }
  }

  Dimension call(std::string_view name, Dimension d) {
    take();  // (
    std::vector<Dimension> args;
    if (!at(Token::Kind::Close)) {
      for (;;) {
        args.push_back(ternary());
        if (!at(Token::Kind::Comma)) break;
        take();
      }
    }
    if (!at(Token::Kind::Close)) throw GiveUp{};
    d.end = take().pos + 1;
    if (args.empty()) throw GiveUp{};
    auto result = [&](Dimension r) {
      r.begin = d.begin;
      r.end = d.end;
      return r;
    };
    const std::string what = fmt::format("the arguments of {}()", name);
    if (name == "min" || name == "max" || name == "sum" || name == "avg" || name == "atan2") {
      Dimension r = args[0];
      for (size_t k = 1; k < args.size(); ++k) r = same(r, args[k], what);
      return name == "atan2" ? result(Dimension::of(Dim::Angle)) : result(r);
    }
    if (name == "abs" || name == "floor" || name == "ceil" || name == "rint") return result(args[0]);
    if (name == "sqrt") {
      Dimension r = args[0];
      if (r.kind != Dimension::Kind::Known) return result(r);
      for (int k = 0; k < 4; ++k) {
        if (r.e[k] % 2 != 0) return result({Dimension::Kind::Unknown});
        r.e[k] = static_cast<int8_t>(r.e[k] / 2);
      }
      return result(r);
    }
    if (name == "asin" || name == "acos" || name == "atan" || name == "rad") return result(Dimension::of(Dim::Angle));
    if (name == "deg") return result(Dimension{});  // degrees, as a plain number
    // sin, cos, tan, exp, logarithms, sign: pure numbers.
    return result(Dimension::of(Dim::None));
  }
};

}  // namespace

namespace {
/// A parser with sscs's operators, functions and constants defined, which every expression's
/// parser copies: defining them takes longer than reading a short expression (a vault of 143
/// drums spent 9 ms of a 0.19 s run setting up parsers).
const mu::Parser& prototype() {
  static const mu::Parser defined = [] {
    mu::Parser p;
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
    return p;
  }();
  return defined;
}
}  // namespace

struct Expression::Impl {
  mu::Parser parser = prototype();
  std::deque<double> slots;  // deque: pointers stay valid as it grows
  std::vector<double*> bound;  // slot of names_[i]
};

Expression::Expression() : impl_(std::make_unique<Impl>()) {}
Expression::Expression(Expression&&) noexcept = default;
Expression& Expression::operator=(Expression&&) noexcept = default;
Expression::~Expression() = default;

std::optional<Expression> Expression::parse(std::string_view text, Error* error, Literals literals) {
  Expression e;
  e.text_ = std::string(text);
  const Internal internal = with_literals_converted(text, literals);
  mu::Parser& p = e.impl_->parser;
  try {
    p.SetVarFactory(new_slot, &e.impl_->slots);
    p.SetExpr(internal.text);
    // Compiled to bytecode now (syntax errors surface here); the values are all 0, the result
    // is ignored. Every variable it defines it reads: the factory made each as the parse met it
    // (GetUsedVar would parse the text once more: a third of the time of parsing).
    p.Eval();
    for (const auto& [name, ptr] : p.GetVar()) {  // std::map: sorted by name
      e.names_.push_back(name);
      e.impl_->bound.push_back(ptr);
    }
  } catch (const mu::Parser::exception_type& ex) {
    if (error) {
      error->message = ex.GetMsg();
      error->position = internal.written.original(static_cast<size_t>(std::max(0, ex.GetPos())));
      // A number followed by a word that is no unit (`2 inch`): say so, not "Unexpected variable".
      const std::vector<Token> tokens = tokenize(text);
      for (size_t k = 0; k + 1 < tokens.size(); ++k)
        if (tokens[k].kind == Token::Kind::Number && !tokens[k].unit && tokens[k + 1].kind == Token::Kind::Name) {
          const std::string word(text.substr(tokens[k + 1].pos, tokens[k + 1].len));
          error->message = fmt::format("'{}' after the number {} is not a unit{} (units: {})", word,
                                       text.substr(tokens[k].pos, tokens[k].len), did_you_mean(word, unit_words()),
                                       known_units(Dim::None));
          error->position = tokens[k + 1].pos;
          break;
        }
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

Expression::Dimensions Expression::check_dimensions(const DimOf& dim_of, const Excerpt& excerpt) const {
  const std::vector<Token> tokens = tokenize(text_);
  return DimensionReader(text_, tokens, dim_of, excerpt).read();
}

// ---- margin splitting ----------------------------------------------------------------------

namespace {

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
  text = trim_blanks(text);
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
    text = trim_blanks(text.substr(1, text.size() - 2));
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
    std::string_view rest = trim_blanks(text.substr(1));
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
  std::string_view lhs = trim_blanks(text.substr(0, h.pos));
  std::string_view rhs = trim_blanks(text.substr(h.pos + h.op.size()));
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
