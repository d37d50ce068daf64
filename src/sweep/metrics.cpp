#include "sweep/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "check/check.h"
#include "compile/compile.h"
#include "compile/values.h"
#include "core/names.h"
#include "core/selection_calls.h"

namespace sscs {

namespace {

const std::vector<std::string> kCounts = {"passed", "failed", "warnings"};

}  // namespace

/// The dimension of `member` on the workcell's objects: of the first type with such an attribute,
/// or of a pose or bounding-box member; nullopt when no type has it.
std::optional<Dim> member_dim(const Workcell& wc, const std::string& member) {
  for (const ObjectType& t : wc.types)
    if (int a = t.find_attribute(member); a >= 0) return t.attributes[a].dim;
  std::string why;
  if (!wc.objects.empty())
    if (auto op = member_operand(wc, 0, member, /*allow_bbox=*/true, &why)) return op->dim;
  return std::nullopt;
}

const std::vector<std::string>& run_fields() {
  static const std::vector<std::string> fields = {"cycle_time", "simulated", "collisions", "events"};
  return fields;
}

const std::vector<std::string>& campaign_fields() {
  static const std::vector<std::string> fields = {"throughput", "makespan", "wait_mean", "wait_max", "jobs_done", "jobs_failed"};
  return fields;
}

namespace {

/// `utilization(DEVICE)` is read as the variable `utilization_DEVICE_`: as long as what it
/// replaces, so the columns of errors stay where the file has them.
constexpr std::string_view kUtilization = "utilization(";

std::string utilization_variables(std::string text) {
  for (size_t at = text.find(kUtilization); at != std::string::npos; at = text.find(kUtilization, at + 1)) {
    const bool word_start = at == 0 || !(std::isalnum(static_cast<unsigned char>(text[at - 1])) || text[at - 1] == '_');
    const size_t close = text.find(')', at);
    if (!word_start || close == std::string::npos) continue;
    std::string_view device = trim_blanks(std::string_view(text).substr(at + kUtilization.size(), close - at - kUtilization.size()));
    if (!is_valid_name(std::string(device)) || device.find('-') != std::string_view::npos) continue;
    text[at + kUtilization.size() - 1] = '_';
    text[close] = '_';
  }
  return text;
}

/// The device of a variable `utilization_DEVICE_`, or "".
std::string utilization_device(std::string_view name) {
  if (!name.starts_with("utilization_") || !name.ends_with("_") || name.size() <= kUtilization.size() + 1) return "";
  return std::string(trim_blanks(name.substr(kUtilization.size(), name.size() - kUtilization.size() - 1)));
}

}  // namespace

std::optional<Metric> Metric::parse(const MetricSpec& spec, Diagnostics& diag) {
  using K = SelectionCall::Kind;
  Metric m;
  m.spec_ = spec;
  const std::string text = utilization_variables(spec.expr.text);
  Expression::Error err;
  auto rewritten = rewrite_selection_calls(text, {K::Count, K::Sum, K::Min, K::Max, K::Avg, K::MinMargin, K::Margin}, &err);
  if (!rewritten) {
    diag.error(mark_at(spec.expr, err.position), fmt::format("metric '{}': {}", spec.name, err.message));
    return std::nullopt;
  }
  auto expr = Expression::parse(rewritten->text, &err, Expression::Literals::FileUnits);
  if (!expr) {
    diag.error(mark_at(spec.expr, rewritten->original(err.position)),
               fmt::format("metric '{}': {} in '{}'", spec.name, without_position(err.message), text));
    return std::nullopt;
  }
  m.calls_ = rewritten->calls;
  m.rewritten_ = std::move(*rewritten);
  m.expr_ = std::make_shared<const Expression>(std::move(*expr));
  return m;
}

void Metric::validate(const Workcell& wc, bool simulated, bool campaign, Diagnostics& diag) const {
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
    if (c.kind != K::Count && !member_dim(wc, c.attribute)) {
      // The member must be one of some type's (checked on the types, as a variant may select
      // other objects), or a pose or bounding-box member every object has.
      std::string why;
      if (!wc.objects.empty() && !member_operand(wc, 0, c.attribute, true, &why) && why.starts_with("expected"))
        diag.error(where(c.arg_position), fmt::format("metric '{}': {}", spec_.name, why));
      else
        diag.error(where(c.position), fmt::format("metric '{}': no type has an attribute '{}'", spec_.name, c.attribute));
    }
  }
  for (const std::string& name : expr_->names()) {
    if (RewrittenExpression::call_index(name) >= 0) continue;
    const bool is_campaign = std::find(campaign_fields().begin(), campaign_fields().end(), name) != campaign_fields().end() ||
                             !utilization_device(name).empty();
    if (is_campaign && !campaign) {
      diag.error(spec_.expr.mark, fmt::format("metric '{}' reads '{}', which only a sweep of a campaign has (campaign:)", spec_.name,
                                              utilization_device(name).empty() ? name : fmt::format("utilization({})", utilization_device(name))));
      continue;
    }
    if (const std::string d = utilization_device(name); !d.empty()) {
      const int o = wc.find_object(d);
      if (o < 0) {
        std::vector<std::string> names;
        for (const Object& x : wc.objects) names.push_back(x.name);
        diag.error(spec_.expr.mark, fmt::format("metric '{}': utilization({}) names no object of vault '{}'{}", spec_.name, d, wc.name,
                                                did_you_mean(d, names)));
      }
      continue;
    }
    if (is_campaign) continue;
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
  auto dim_of = [&](std::string_view name) -> std::optional<Dim> {
    if (int call = RewrittenExpression::call_index(name); call >= 0 && call < static_cast<int>(calls_.size())) {
      const SelectionCall& c = calls_[call];
      if (c.kind == SelectionCall::Kind::Count) return Dim::None;
      if (c.kind == SelectionCall::Kind::MinMargin || c.kind == SelectionCall::Kind::Margin) return std::nullopt;  // each in its check's unit
      auto d = member_dim(wc, c.attribute);
      return d && *d != Dim::None ? d : std::nullopt;
    }
    if (name == "cycle_time" || name == "simulated" || name == "makespan" || name == "wait_mean" || name == "wait_max") return Dim::Time;
    if (name == "jobs_done" || name == "jobs_failed" || !utilization_device(name).empty()) return Dim::None;
    if (name == "throughput") return std::nullopt;  // jobs per hour
    if (name == "collisions" || name == "events" || std::find(kCounts.begin(), kCounts.end(), name) != kCounts.end())
      return Dim::None;
    auto p = std::find_if(wc.parameters.begin(), wc.parameters.end(), [&](const Parameter& x) { return x.name == name; });
    if (p == wc.parameters.end() || p->dim == Dim::None) return std::nullopt;
    return p->dim;
  };
  Expression::Dimensions d = expr_->check_dimensions(dim_of, [&](size_t begin, size_t end) {
    const size_t b = std::min(rewritten_.original(begin), spec_.expr.text.size());
    const size_t n = std::min(rewritten_.original(end), spec_.expr.text.size());
    return spec_.expr.text.substr(b, n > b ? n - b : 0);
  });
  if (d.error)
    diag.error(where(rewritten_.original(d.error->position)), fmt::format("metric '{}': {} in '{}'", spec_.name, d.error->message,
                                                                           spec_.expr.text));
}

Expected<double> Metric::evaluate(const Workcell& wc, const GeometryModel& geometry, const CheckReport& report,
                                  const RunSummary* run) const {
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
        // What each object holds, read as a vault's expression reads it (compile's member_operand).
        Operand aggregate;
        aggregate.kind = Operand::Kind::Aggregate;
        aggregate.aggregate = static_cast<uint8_t>(c.kind);
        auto members = std::make_shared<std::vector<Operand>>();
        for (int o : *objects) {
          std::string problem;
          auto m = member_operand(wc, o, c.attribute, /*allow_bbox=*/true, &problem);
          if (!m) {
            why = fmt::format("metric '{}': {}", spec_.name, problem);
            return kNaN;
          }
          if (members->empty()) aggregate.dim = m->dim;
          members->push_back(std::move(*m));
        }
        aggregate.members = std::move(members);
        return si_to_file(operand_value(aggregate, wc.values, geometry), aggregate.dim);
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
    } else if (const std::string d = utilization_device(name); run && !d.empty()) {
      double u = kNaN;
      if (run->campaign)
        for (const auto& [device, use] : run->campaign->devices)
          if (device == d) u = use.utilization;
      if (std::isnan(u)) why = fmt::format("metric '{}': {} takes no jobs of this campaign", spec_.name, d);
      values.push_back(u);
    } else if (run && std::find(campaign_fields().begin(), campaign_fields().end(), name) != campaign_fields().end()) {
      if (!run->campaign) return Unexpected{fmt::format("metric '{}': '{}' is a campaign's, and this run is none", spec_.name, name)};
      const RunSummaryFile::Campaign& c = *run->campaign;
      values.push_back(name == "throughput" ? c.throughput : name == "makespan" ? c.makespan : name == "wait_mean" ? c.wait_mean
                       : name == "wait_max" ? c.wait_max : name == "jobs_done" ? static_cast<double>(c.done)
                                                                : static_cast<double>(c.failed));
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
