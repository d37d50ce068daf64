#pragma once
/// Data shared by the compile passes (internal to compile/). Each pass is a function over it.
#include <array>
#include <memory>
#include <string>
#include <unordered_map>
#include <set>
#include <unordered_set>
#include <vector>

#include "compile/compile.h"
#include "compile/workcell.h"
#include "core/diagnostics.h"
#include "core/expr.h"

namespace sscs {

/// A value still to compute: an expression over other slots, in dependency order.
struct PendingValue {
  uint32_t slot = 0;
  const Scalar* source = nullptr;
  std::shared_ptr<const Expression> expr;
  std::vector<Operand> inputs;  ///< one per expr->names(): slots or constants (array indices)
  double add = 0;               ///< array offset added to a location
  uint8_t state = 0;            ///< 0 new, 1 visiting, 2 done, 3 failed
};

/// Names an expression may use besides object references.
struct ExprScope {
  int object = -1;                 ///< own object, for bare attribute names in type defaults
  const std::array<int, 3>* index = nullptr;  ///< array indices i, j, k (1-based), or null
};

struct CompileState {
  CompileState(const VaultSpec& s, Sources& src, Diagnostics& d, const FileFacts& f) : spec(s), sources(src), diag(d), files(f) {}

  const VaultSpec& spec;
  Sources& sources;
  Diagnostics& diag;
  const FileFacts& files;  ///< what the files the vault names are (gathered with its inputs)
  Workcell wc;
  std::shared_ptr<PluginSet> plugins;  ///< the loaded plugins' classes
  std::unordered_map<std::string, int> parameter_index;  ///< lookups only, never iterated into output
  std::vector<const ObjectSpec*> object_spec;            ///< per object
  std::vector<std::array<int, 3>> array_index;           ///< per object, {0,0,0} when not in an array
  std::vector<std::array<double, 3>> array_offset;       ///< per object, SI
  std::unordered_set<std::string> unbuilt;  ///< objects dropped by an earlier error: no second error for them
  std::vector<std::string> unbuilt_arrays;  ///< name patterns of arrays dropped by an error (`Row_{i}`)
  std::set<std::string> unbuilt_types;      ///< types whose objects were dropped (unknown, or their files broken)
  /// Whether `name` is an object an earlier error dropped (one named so, or an instance of a
  /// dropped array: one wrong pitch gave one error and then 243 "'at' names unknown object").
  bool is_unbuilt(std::string_view name) const;
  /// Whether a selector item (`Row_*`, `at:Row_1.top_*`) may have selected an object an earlier
  /// error dropped: its emptiness, or its unknown object, follows from that error.
  bool may_select_unbuilt(std::string_view item) const;
  std::set<int> reported_types;  ///< types whose problems (ObjectType::problems) were reported
  std::vector<PendingValue> pending;
  std::vector<int> slot_pending;
  std::vector<bool> slot_failed;                         ///< slot whose value could not be read: no range check                         ///< slot -> index into pending, or -1
  std::unordered_map<std::string, std::shared_ptr<const Expression>> expr_cache;  ///< by text

  uint32_t new_slots(size_t n);
  /// "Room1.height", "parameter aisle": for messages.
  std::string slot_name(uint32_t slot) const;
  std::vector<std::string> object_names() const;
  std::vector<std::string> parameter_names() const;

  /// Parses an expression once per distinct text; reports syntax errors at the scalar's mark.
  std::shared_ptr<const Expression> parse_expression(const Scalar& s, std::string_view what);
  /// Resolves every name of `expr` to an operand; false (with errors reported) when one is unknown.
  /// `allow_bbox`: bounding-box references resolve to deferred operands (constraints only).
  bool resolve_inputs(const Expression& expr, const Scalar& s, const ExprScope& scope, std::vector<Operand>& out,
                      bool allow_bbox = false);
  /// Resolves one reference ("Room1.height", "Obj.location.x", "aisle").
  std::optional<Operand> resolve_reference(std::string_view ref, SourceMark mark, const ExprScope& scope,
                                           bool allow_bbox = false);
  /// Evaluates every pending value in dependency order, reporting cycles with their path.
  void evaluate_pending();
  /// A number given where a value is needed now (an array count, a constraint's tolerance): a
  /// literal with or without a unit, or an expression over parameters (and, unless
  /// `parameters_only`, attributes) evaluated at once; a non-finite result is an input error.
  std::optional<double> number_now(const Scalar& s, Dim dim, std::string_view what, bool parameters_only = false);
};

void compile_constraints(CompileState& st);

}  // namespace sscs
