#pragma once
/// Calls over selections inside an expression: `count(type:drum)`, `sum(Rack_*.level_capacity)`,
/// `min(type:drum.height)`, `max(...)`, `avg(...)`, and for sweep metrics `min_margin()` and
/// `margin(NAME)`. Their arguments are selectors (`type:T`, globs, names), which no expression
/// parser reads, so each call is replaced by a variable `_callN` before parsing; the caller gives
/// those variables their values. One implementation for `expr` constraints and sweep metrics.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/expr.h"

namespace sscs {

struct SelectionCall {
  enum class Kind : uint8_t { Count, Sum, Min, Max, Avg, MinMargin, Margin } kind = Kind::Count;
  std::string selector;    ///< count, sum, min, max, avg: what the call selects (`type:drum`, `Rack_*`)
  std::string attribute;   ///< sum, min, max, avg: what it reads of each (`fill_mass`, `location.z`)
  std::string constraint;  ///< margin: the constraint's name
  size_t position = 0;      ///< of the call's name in the original text
  size_t arg_position = 0;  ///< of its argument
};

const char* selection_call_name(SelectionCall::Kind kind);

struct RewrittenExpression {
  std::string text;                    ///< the calls replaced by `_call0`, `_call1`, ...
  std::vector<SelectionCall> calls;
  /// Where offset `pos` of `text` lies in the original text (for error carets).
  size_t original(size_t pos) const { return offsets.original(pos); }
  /// Index of the call a variable name stands for, or -1.
  static int call_index(std::string_view name);

  OffsetMap offsets;  ///< after each call
};

/// Replaces the calls of the given kinds by variables. `min` and `max` with one argument are
/// aggregates; with two they stay the functions of every expression. A malformed call (an empty
/// or unclosed argument, `sum` without `.attribute`) fills `error` (position in the original).
std::optional<RewrittenExpression> rewrite_selection_calls(std::string_view text, const std::vector<SelectionCall::Kind>& kinds,
                                                           Expression::Error* error);

/// A muparser message without its " at position N" (the caret shows where).
std::string without_position(std::string message);

}  // namespace sscs
