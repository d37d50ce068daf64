#include "compile/values.h"

#include "core/pose.h"
#include "core/selection_calls.h"

#include <algorithm>

#include <fmt/format.h>

namespace sscs {

Dim dim_of(AttrType type) {
  switch (type) {
    case AttrType::Length: return Dim::Length;
    case AttrType::Angle: return Dim::Angle;
    case AttrType::Mass: return Dim::Mass;
    case AttrType::Time: return Dim::Time;
    default: return Dim::None;
  }
}

ParsedValue parse_value(const Scalar& s, Dim dim, std::string_view what, Diagnostics& diag, bool any_dim) {
  ParsedValue out;
  if (s.null || s.text.empty()) {
    diag.error(s.mark, fmt::format("expected {} for {}, found nothing", a_dim(dim), what));
    return out;
  }
  std::string unknown;
  if (auto q = parse_quantity(s.text, &unknown)) {
    if (!q->has_unit) {
      out.kind = ParsedValue::Kind::Number;
      out.si = q->si * file_unit_to_si(dim);
      out.dim = dim;
      return out;
    }
    if (q->dim != dim && !(any_dim && dim == Dim::None)) {
      diag.error(s.mark, fmt::format("expected {} for {}, found '{}' ({})", a_dim(dim), what, s.text,
                                     a_dim(q->dim)));
      return out;
    }
    out.kind = ParsedValue::Kind::Number;
    out.si = q->si;
    out.dim = q->dim;
    return out;
  }
  if (!unknown.empty()) {
    std::string units = known_units(dim);
    diag.error(s.mark, fmt::format("unknown unit '{}' in '{}' for {}; {} units are: {}", unknown, s.text, what,
                                   dim == Dim::None ? "known" : dim_name(dim), units.empty() ? "none" : units));
    return out;
  }
  out.kind = ParsedValue::Kind::Expression;
  return out;
}

std::optional<double> literal_si(const Scalar& s, Dim dim, std::string_view what, Diagnostics& diag) {
  ParsedValue v = parse_value(s, dim, what, diag);
  if (v.kind == ParsedValue::Kind::Number) return v.si;
  if (v.kind == ParsedValue::Kind::Expression)
    diag.error(s.mark, fmt::format("expected {} for {}, found '{}': an expression; a number with its unit is needed here", a_dim(dim), what, s.text));
  return std::nullopt;
}

SourceMark mark_at(const Scalar& s, size_t pos) {
  SourceMark m = s.mark;
  m.column += static_cast<uint32_t>(pos + (s.quoted ? 1 : 0));
  return m;
}

Eigen::Isometry3d literal_pose(const PoseSpec& p, std::string_view what, Diagnostics& diag) {
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero(), rpy = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    if (p.xyz[k].present) xyz[k] = literal_si(p.xyz[k], Dim::Length, fmt::format("{} xyz", what), diag).value_or(0);
    if (p.rpy[k].present) rpy[k] = literal_si(p.rpy[k], Dim::Angle, fmt::format("{} rpy", what), diag).value_or(0);
  }
  return make_pose(xyz, rpy);
}

std::optional<Dim> operand_dim(const Operand& op) {
  if (op.kind == Operand::Kind::Aggregate && static_cast<SelectionCall::Kind>(op.aggregate) == SelectionCall::Kind::Count)
    return Dim::None;
  if (op.dim == Dim::None || op.dim == Dim::Fraction) return std::nullopt;
  return op.dim;
}

bool check_expression_dimensions(const Expression& e, const Expression::DimOf& dim_of, const Scalar& s, Dim expected,
                                 std::string_view what, Diagnostics& diag, const std::function<size_t(size_t)>& column) {
  Expression::Excerpt excerpt;
  if (column)
    excerpt = [&](size_t begin, size_t end) {
      const size_t b = std::min(column(begin), s.text.size()), n = std::min(column(end), s.text.size());
      return s.text.substr(b, n > b ? n - b : 0);
    };
  Expression::Dimensions d = e.check_dimensions(dim_of, excerpt);
  if (d.warning)
    diag.warning(mark_at(s, column ? column(d.warning->position) : d.warning->position),
                 fmt::format("{} in '{}' for {}", d.warning->message, s.text, what));
  if (d.error) {
    diag.error(mark_at(s, column ? column(d.error->position) : d.error->position),
               fmt::format("{} in '{}' for {}", d.error->message, s.text, what));
    return false;
  }
  if (expected != Dim::None && expected != Dim::Fraction && d.known && d.dim != expected) {
    diag.error(s.mark, fmt::format("expected {} for {}, found '{}', which is {}", a_dim(expected), what, s.text, d.described));
    return false;
  }
  return true;
}

namespace {
/// The dimension of each name `e` reads, from its operands (one per `e.names()`).
Expression::DimOf dims_of_inputs(const Expression& e, const std::vector<Operand>& inputs) {
  return [&e, &inputs](std::string_view name) -> std::optional<Dim> {
    const std::vector<std::string>& names = e.names();
    auto it = std::lower_bound(names.begin(), names.end(), name);
    if (it == names.end() || *it != name || static_cast<size_t>(it - names.begin()) >= inputs.size()) return std::nullopt;
    return operand_dim(inputs[it - names.begin()]);
  };
}
}  // namespace

bool check_expression_dimensions(const Expression& e, const std::vector<Operand>& inputs, const Scalar& s, Dim expected,
                                 std::string_view what, Diagnostics& diag, const std::function<size_t(size_t)>& column) {
  return check_expression_dimensions(e, dims_of_inputs(e, inputs), s, expected, what, diag, column);
}

std::optional<Dim> expression_dim(const Expression& e, const std::vector<Operand>& inputs) {
  const Expression::Dimensions d = e.check_dimensions(dims_of_inputs(e, inputs));
  if (d.error || !d.known) return std::nullopt;
  return d.dim;
}

}  // namespace sscs
