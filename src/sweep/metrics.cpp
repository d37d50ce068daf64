#include "sweep/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "compile/values.h"
#include "core/names.h"
#include "core/selection_calls.h"

namespace sscs {

namespace {

const std::vector<std::string> kCounts = {"passed", "failed", "warnings"};

}  // namespace

const std::vector<std::string>& run_fields() {
  static const std::vector<std::string> fields = {"cycle_time", "simulated", "collisions", "events"};
  return fields;
}

std::optional<Metric> Metric::parse(const MetricSpec& spec, Diagnostics& diag) {
  using K = SelectionCall::Kind;
  Metric m;
  m.spec_ = spec;
  const std::string& text = spec.expr.text;
  Expression::Error err;
  auto rewritten = rewrite_selection_calls(text, {K::Count, K::Sum, K::Min, K::Max, K::Avg, K::MinMargin, K::Margin}, &err);
  if (!rewritten) {
    diag.error(mark_at(spec.expr, err.position), fmt::format("metric '{}': {}", spec.name, err.message));
    return std::nullopt;
  }
  auto expr = Expression::parse(rewritten->text, &err);
  if (!expr) {
    diag.error(mark_at(spec.expr, rewritten->original(err.position)),
               fmt::format("metric '{}': {} in '{}'", spec.name, without_position(err.message), text));
    return std::nullopt;
  }
  m.calls_ = std::move(rewritten->calls);
  m.expr_ = std::make_shared<const Expression>(std::move(*expr));
  return m;
}

void Metric::validate(const Workcell& wc, bool simulated, Diagnostics& diag) const {
  auto where = [&](size_t pos) { return mark_at(spec_.expr, pos); };
  using K = SelectionCall::Kind;
  for (const SelectionCall& c : calls_) {
    if (c.kind == K::Margin) {
      bool found = std::any_of(wc.constraints.begin(), wc.constraints.end(), [&](const Constraint& k) { return k.name == c.constraint; });
      if (!found) {
        std::vector<std::string> names;
        for (const Constraint& k : wc.constraints) names.push_back(k.name);
        std::string hint = did_you_mean(c.constraint, names);
        if (hint.empty() && !names.empty() && names.size() <= 12) hint = fmt::format("; its constraints: {}", fmt::join(names, ", "));
        diag.error(where(c.position), fmt::format("metric '{}': vault '{}' has no constraint '{}'{}", spec_.name, wc.name,
                                                  c.constraint, hint));
      }
    }
    if (c.kind == K::MinMargin || c.kind == K::Margin) continue;
    if (c.selector.starts_with("type:") && wc.find_type(c.selector.substr(5)) < 0) {
      std::vector<std::string> names;
      for (const ObjectType& t : wc.types) names.push_back(t.name);
      diag.error(where(c.position), fmt::format("metric '{}': unknown type '{}'{}", spec_.name, c.selector.substr(5),
                                                did_you_mean(c.selector.substr(5), names)));
      continue;
    }
    if (c.kind != K::Count) {
      // The attribute must be one of the selected objects' types (checked on the types, as a
      // variant may select other objects).
      bool known = false;
      for (const ObjectType& t : wc.types) known |= t.find_attribute(c.attribute) >= 0;
      for (int k = kLocationSlot; k < kLocationSlot + 3; ++k) known |= c.attribute == kPoseSlotNames[k];
      if (!known)
        diag.error(where(c.position), fmt::format("metric '{}': no type has an attribute '{}'", spec_.name, c.attribute));
    }
  }
  for (const std::string& name : expr_->names()) {
    if (RewrittenExpression::call_index(name) >= 0) continue;
    bool is_run = std::find(run_fields().begin(), run_fields().end(), name) != run_fields().end();
    if (is_run && !simulated) {
      diag.error(spec_.expr.mark, fmt::format("metric '{}' reads '{}', which only a simulated sweep has (add scenario:)", spec_.name, name));
      continue;
    }
    bool is_param = std::any_of(wc.parameters.begin(), wc.parameters.end(), [&](const Parameter& p) { return p.name == name; });
    if (is_run || is_param || std::find(kCounts.begin(), kCounts.end(), name) != kCounts.end()) continue;
    std::vector<std::string> names(kCounts);
    for (const Parameter& p : wc.parameters) names.push_back(p.name);
    if (simulated) names.insert(names.end(), run_fields().begin(), run_fields().end());
    diag.error(spec_.expr.mark, fmt::format("metric '{}' reads '{}', which is no parameter of vault '{}', no count and no "
                                            "run field{}", spec_.name, name, wc.name, did_you_mean(name, names)));
  }
}

Expected<double> Metric::evaluate(const Workcell& wc, const CheckReport& report, const RunSummary* run) const {
  std::string why;  // the first reason the value is undefined
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  using K = SelectionCall::Kind;
  auto call_value = [&](const SelectionCall& c) -> double {
    switch (c.kind) {
      case K::MinMargin:
      case K::Margin: {
        double best = kNaN;
        for (const CheckResult& r : report.results) {
          if (!r.margin || !std::isfinite(*r.margin)) continue;
          if (c.kind == K::Margin && wc.constraints[r.constraint].name != c.constraint) continue;
          best = std::isnan(best) ? *r.margin : std::min(best, *r.margin);
        }
        if (std::isnan(best))
          why = c.kind == K::Margin ? fmt::format("metric '{}': constraint '{}' has no margin in this variant", spec_.name, c.constraint)
                                      : fmt::format("metric '{}': no check has a margin in this variant", spec_.name);
        return best;
      }
      default: {
        auto objects = wc.select(c.selector);
        if (c.kind == K::Count) return objects ? static_cast<double>(objects->size()) : 0.0;  // a name this variant lacks
        if (!objects || objects->empty()) {
          // Undefined for this variant: an empty cell, and why (docs/sweeps.md).
          why = fmt::format("metric '{}': {}({}.{}) selects no object in this variant", spec_.name, selection_call_name(c.kind),
                               c.selector, c.attribute);
          return kNaN;
        }
        double total = 0, lo = INFINITY, hi = -INFINITY;
        for (int o : *objects) {
          const Object& obj = wc.objects[o];
          double x;
          if (c.attribute.starts_with("location.") && c.attribute.size() == 10) {
            x = wc.values[obj.first_slot + kLocationSlot + (c.attribute.back() - 'x')];
          } else {
            const ObjectType& t = wc.types[obj.type];
            int a = t.find_attribute(c.attribute);
            if (a < 0) {
              why = fmt::format("metric '{}': {} ({}) has no attribute '{}'", spec_.name, obj.name, t.name, c.attribute);
              return kNaN;
            }
            x = si_to_file(wc.values[obj.first_slot + kFirstAttributeSlot + a], t.attributes[a].dim);
          }
          total += x;
          lo = std::min(lo, x);
          hi = std::max(hi, x);
        }
        switch (c.kind) {
          case K::Min: return lo;
          case K::Max: return hi;
          case K::Avg: return total / static_cast<double>(objects->size());
          default: return total;
        }
      }
    }
  };
  std::vector<double> values;
  for (const std::string& name : expr_->names()) {
    if (int call = RewrittenExpression::call_index(name); call >= 0) {
      values.push_back(call_value(calls_[call]));
    } else if (name == "passed" || name == "failed" || name == "warnings") {
      values.push_back(static_cast<double>(name == "passed" ? report.passed : name == "failed" ? report.failed : report.warnings));
    } else if (run && name == "cycle_time") {
      values.push_back(run->cycle_time);
    } else if (run && name == "simulated") {
      values.push_back(run->simulated);
    } else if (run && name == "collisions") {
      values.push_back(static_cast<double>(run->collisions));
    } else if (run && name == "events") {
      values.push_back(static_cast<double>(run->events));
    } else {
      auto p = std::find_if(wc.parameters.begin(), wc.parameters.end(), [&](const Parameter& x) { return x.name == name; });
      if (p == wc.parameters.end()) return Unexpected{fmt::format("metric '{}': '{}' is no parameter of this variant", spec_.name, name)};
      values.push_back(si_to_file(wc.values[p->slot], p->dim));
    }
    if (!why.empty()) return Unexpected{why};
  }
  const double value = expr_->evaluate(values.data());
  // A non-finite value is no value: an empty cell, and why (never a silent one).
  if (!std::isfinite(value))
    return Unexpected{fmt::format("metric '{}' is {} in this variant (a division by zero?)", spec_.name, std::isnan(value) ? "not a number" : "infinite")};
  return value;
}

}  // namespace sscs
