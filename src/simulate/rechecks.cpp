#include "simulate/rechecks.h"

#include <algorithm>
#include <string>
#include <variant>

#include "core/units.h"

namespace sscs {

ConstraintRechecks::ConstraintRechecks(const Workcell& wc, const std::set<int>& moving, double tolerance) : wc_(wc) {
  options_.describe_passes = false;
  options_.spatial_tolerance = tolerance;
  std::vector<char> only(wc.constraints.size(), 0);
  bool any = false;
  for (size_t i = 0; i < wc.constraints.size(); ++i) {
    const Constraint& c = wc.constraints[i];
    const auto* spatial = std::get_if<SpatialCheck>(&c.body);
    bool kind = std::holds_alternative<BoundCheck>(c.body) || std::holds_alternative<ExprCheck>(c.body) ||
                (spatial && spatial->kind != SpatialCheck::Kind::NoOverlap);
    bool reads = std::any_of(c.subjects.begin(), c.subjects.end(), [&](int o) { return moving.count(o) > 0; });
    only[i] = kind && reads;
    any = any || only[i];
  }
  if (any) options_.only = std::move(only);
}

void ConstraintRechecks::check(double t, const GeometryModel& live, const std::vector<double>& values, EventLog& events) {
  CheckReport report = sscs::check(wc_, live, values, options_);
  for (const CheckResult& r : report.results) {
    auto key = std::make_pair(r.constraint, r.subjects);
    bool failing = r.status != Status::Pass;
    bool was = failing_[key];
    failing_[key] = failing;
    if (!failing || was) continue;
    const Constraint& c = wc_.constraints[r.constraint];
    std::vector<std::string> subjects;
    for (int o : r.subjects) subjects.push_back(wc_.objects[o].name);
    nlohmann::ordered_json f = {{"constraint", c.name}, {"severity", c.severity == Severity::Warning ? "warning" : "error"},
                                {"subjects", subjects}};
    if (r.margin) f["margin"] = r9(*r.margin);
    f["unit"] = file_unit(r.dim);
    f["message"] = r.message;
    events.add(t, EventKind::Constraint, f);
    if (c.severity != Severity::Warning) ++failures_;
  }
}

}  // namespace sscs
