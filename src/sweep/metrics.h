#pragma once
/// A sweep's metrics: expressions over a variant's outcome. Besides + - * / and the functions of
/// every sscs expression they may call
///   count(SELECTOR)            objects selected (`type:drum`, `Rack_*`, `*`, a name)
///   sum(SELECTOR.member)       what a vault expression reads of each selected object (an
///                              attribute, location.x, bbox.max.y: compile's member_operand),
///                              summed, in file units; SELECTOR as anywhere (a list, at:, !)
///   min/max/avg(SELECTOR.member)  its smallest, largest, mean value (undefined for no object)
///   min_margin()               the smallest margin of any check (file units of each check)
///   margin(CONSTRAINT NAME)    the smallest margin of that constraint's checks
/// and read the variables passed, failed, warnings, any vault parameter (file units) and, when a
/// scenario is simulated, cycle_time, simulated, collisions and events. Numbers with units
/// (`2 min`, `90 deg`) are in file units, as every value a metric reads; sides of + - and
/// comparisons must have one dimension (an error at the token, as in a vault's `expr`).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "check/check.h"
#include "compile/workcell.h"
#include "geometry/geometry.h"
#include "core/diagnostics.h"
#include "core/expected.h"
#include "core/expr.h"
#include "core/selection_calls.h"
#include "load/sweep.h"
#include "simulate/simulate.h"

namespace sscs {

class Metric {
 public:
  /// Parses the metric's expression; reports syntax errors and unknown functions at their column.
  static std::optional<Metric> parse(const MetricSpec& spec, Diagnostics& diag);

  /// Reports what the metric names that `wc` (a variant's vault as written, before its values
  /// change) does not have: types and objects in selectors, attributes, constraints, variables;
  /// and run fields when the sweep simulates nothing (campaign fields when it runs no campaign).
  void validate(const Workcell& wc, bool simulated, bool campaign, Diagnostics& diag) const;

  /// The metric of one variant, or why it has none: undefined (min_margin() of no margins, a
  /// selector that selects nothing), not computable (a selected object lacking the attribute) or
  /// not finite (a division by zero). The table leaves its cell empty and says why.
  Expected<double> evaluate(const Workcell& wc, const GeometryModel& geometry, const CheckReport& report, const RunSummary* run) const;

  const std::string& name() const { return spec_.name; }

 private:
  MetricSpec spec_;
  std::vector<SelectionCall> calls_;        ///< stand in the expression as the variables `_call0`, `_call1`, ...
  RewrittenExpression rewritten_;           ///< the text parsed, for positions as written
  std::shared_ptr<const Expression> expr_;  ///< shared: metrics are copied into each worker
};

/// The variables a metric reads besides calls: run fields (only when a scenario is simulated).
const std::vector<std::string>& run_fields();
/// What a sweep of a campaign adds: throughput, makespan, wait_mean, wait_max, jobs_done,
/// jobs_failed (and utilization(DEVICE)).
const std::vector<std::string>& campaign_fields();

}  // namespace sscs
