#include "core/expr.h"

#include <muParser.h>

#include <cmath>
#include <deque>
#include <numbers>

namespace sscs {

namespace {
double op_not(double x) { return x == 0 ? 1.0 : 0.0; }
double fn_floor(double x) { return std::floor(x); }
double fn_ceil(double x) { return std::ceil(x); }
double fn_deg(double x) { return x * 180.0 / std::numbers::pi; }
double fn_rad(double x) { return x * std::numbers::pi / 180.0; }

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
    p.DefineInfixOprt("!", op_not);
    p.DefineFun("floor", fn_floor);
    p.DefineFun("ceil", fn_ceil);
    p.DefineFun("deg", fn_deg);
    p.DefineFun("rad", fn_rad);
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
    return impl_->parser.Eval();
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

}  // namespace sscs
