#pragma once
/// Reading written values as SI numbers: plain numbers in file units, unit literals with a
/// dimension check, or expressions (parsed later in dependency order). Internal to compile.
#include <Eigen/Geometry>

#include <functional>
#include <optional>
#include <string_view>

#include "compile/workcell.h"
#include "core/diagnostics.h"
#include "core/expr.h"
#include "core/units.h"
#include "load/spec.h"

namespace sscs {

Dim dim_of(AttrType type);

struct ParsedValue {
  enum class Kind { Number, Expression, Error } kind = Kind::Error;
  double si = 0;
  Dim dim = Dim::None;  ///< the dimension its unit gave it (None for a plain number)
};

/// Reads `s` as a value of dimension `dim` (Dim::None accepts any unit and reports it in .dim
/// when `any_dim`). Reports wrong and unknown units; anything else that is no number is an
/// expression for the caller to parse.
ParsedValue parse_value(const Scalar& s, Dim dim, std::string_view what, Diagnostics& diag, bool any_dim = false);

/// Like parse_value but an expression is an error: for limits, tolerances and type bounds.
std::optional<double> literal_si(const Scalar& s, Dim dim, std::string_view what, Diagnostics& diag);

/// A pose written with literal values (file units; no expressions): a target, an offset.
Eigen::Isometry3d literal_pose(const PoseSpec& p, std::string_view what, Diagnostics& diag);

/// Where an expression's column `pos` lands in the file: the scalar's mark plus the offset,
/// plus one for the opening quote.
SourceMark mark_at(const Scalar& s, size_t pos);

/// What a compiled operand is to the dimension check: its dimension, Dim::None for a count,
/// nullopt for a value written without a unit (a plain parameter, an array index), which fits any.
std::optional<Dim> operand_dim(const Operand& op);

/// Runs the dimension check of `e` (Expression::check_dimensions) and reports a mismatch at its
/// column in `s`; when `expected` is a dimension (not Dim::None), a result of another dimension
/// is an error too ("expected a length for X, found ..., which is a mass"). `column` maps a
/// position of the text `e` was parsed from to one of `s` (identity when empty). True when clean.
bool check_expression_dimensions(const Expression& e, const Expression::DimOf& dim_of, const Scalar& s, Dim expected,
                                 std::string_view what, Diagnostics& diag, const std::function<size_t(size_t)>& column = {});

/// The dimension of `e`'s result with the dimensions of `inputs` (one per `e.names()`), when it
/// has one sscs names; nullopt for a plain number or one the check cannot follow.
std::optional<Dim> expression_dim(const Expression& e, const std::vector<Operand>& inputs);

/// check_expression_dimensions with the dimensions of `inputs`, one per `e.names()`.
bool check_expression_dimensions(const Expression& e, const std::vector<Operand>& inputs, const Scalar& s, Dim expected,
                                 std::string_view what, Diagnostics& diag, const std::function<size_t(size_t)>& column = {});

}  // namespace sscs
