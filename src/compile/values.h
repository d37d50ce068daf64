#pragma once
/// Reading written values as SI numbers: plain numbers in file units, unit literals with a
/// dimension check, or expressions (parsed later in dependency order). Internal to compile.
#include <Eigen/Geometry>

#include <string_view>

#include "core/diagnostics.h"
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

}  // namespace sscs
