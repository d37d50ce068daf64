#include "sweep/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "compile/values.h"
#include "core/names.h"

namespace sscs {

namespace {

bool ident_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool ident_char(char c) { return ident_start(c) || (c >= '0' && c <= '9') || c == '.'; }

std::string trim(std::string_view s) {
  size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  if (a == std::string_view::npos) return {};
  std::string out(s.substr(a, b - a + 1));
  if (out.size() >= 2 && (out.front() == '"' || out.front() == '\'') && out.back() == out.front()) out = out.substr(1, out.size() - 2);
  return out;
}

const std::vector<std::string> kCounts = {"passed", "failed", "warnings"};

}  // namespace

const std::vector<std::string>& run_fields() {
  static const std::vector<std::string> fields = {"cycle_time", "simulated", "collisions", "events"};
  return fields;
}

std::optional<Metric> Metric::parse(const MetricSpec& spec, Diagnostics& diag) {
  Metric m;
  m.spec_ = spec;
  const std::string& text = spec.expr.text;
  std::string rewritten;
  for (size_t i = 0; i < text.size();) {
    if (!ident_start(text[i]) || (i > 0 && ident_char(text[i - 1]))) {
      rewritten += text[i++];
      continue;
    }
    size_t end = i;
    while (end < text.size() && ident_char(text[end])) ++end;
    std::string word = text.substr(i, end - i);
    size_t open = end;
    while (open < text.size() && text[open] == ' ') ++open;
    bool called = open < text.size() && text[open] == '(';
    static const std::vector<std::string> kFunctions = {"count", "sum", "min_margin", "margin"};
    if (!called || std::find(kFunctions.begin(), kFunctions.end(), word) == kFunctions.end()) {
      rewritten += word;
      i = end;
      continue;
    }
    int depth = 0;
    size_t close = open;
    for (; close < text.size(); ++close) {
      depth += text[close] == '(' ? 1 : text[close] == ')' ? -1 : 0;
      if (depth == 0) break;
    }
    if (close >= text.size()) {
      diag.error(mark_at(spec.expr, open), fmt::format("metric '{}': '(' of {}() is never closed", spec.name, word));
      return std::nullopt;
    }
    std::string arg = trim(std::string_view(text).substr(open + 1, close - open - 1));
    Call call;
    call.position = i;
    if (word == "min_margin") {
      call.kind = Call::Kind::MinMargin;
      if (!arg.empty()) diag.error(mark_at(spec.expr, open + 1), fmt::format("metric '{}': min_margin() takes no argument", spec.name));
    } else if (word == "margin") {
      call.kind = Call::Kind::Margin;
      call.constraint = arg;
      if (arg.empty()) diag.error(mark_at(spec.expr, open + 1), fmt::format("metric '{}': margin() needs a constraint name, as margin(door clear height)", spec.name));
    } else if (word == "count") {
      call.kind = Call::Kind::Count;
      call.selector = arg;
      if (arg.empty()) diag.error(mark_at(spec.expr, open + 1), fmt::format("metric '{}': count() needs a selector, as count(type:drum)", spec.name));
    } else {
      call.kind = Call::Kind::Sum;
      size_t dot = arg.rfind('.');
      if (dot == std::string::npos || dot == 0 || dot + 1 == arg.size()) {
        diag.error(mark_at(spec.expr, open + 1), fmt::format("metric '{}': sum() needs SELECTOR.attribute, as sum(type:rack.levels), found '{}'", spec.name, arg));
      } else {
        call.selector = arg.substr(0, dot);
        call.attribute = arg.substr(dot + 1);
      }
    }
    rewritten += fmt::format("_call{}", m.calls_.size());
    m.calls_.push_back(call);
    i = close + 1;
  }
  Expression::Error err;
  auto expr = Expression::parse(rewritten, &err);
  if (!expr) {
    // Positions in the rewritten text differ after a call; point at the metric when they might.
    SourceMark where = m.calls_.empty() ? mark_at(spec.expr, err.position) : spec.expr.mark;
    std::string message = err.message;
    if (size_t at = message.find(" at position "); at != std::string::npos && !m.calls_.empty()) message.resize(at);
    diag.error(where, fmt::format("metric '{}': {} in '{}'", spec.name, message, text));
    return std::nullopt;
  }
  m.expr_ = std::make_shared<const Expression>(std::move(*expr));
  return m;
}

void Metric::validate(const Workcell& wc, bool simulated, Diagnostics& diag) const {
  auto where = [&](size_t pos) { return mark_at(spec_.expr, pos); };
  for (const Call& c : calls_) {
    if (c.kind == Call::Kind::Margin) {
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
    if (c.kind != Call::Kind::Count && c.kind != Call::Kind::Sum) continue;
    if (c.selector.starts_with("type:") && wc.find_type(c.selector.substr(5)) < 0) {
      std::vector<std::string> names;
      for (const ObjectType& t : wc.types) names.push_back(t.name);
      diag.error(where(c.position), fmt::format("metric '{}': unknown type '{}'{}", spec_.name, c.selector.substr(5),
                                                did_you_mean(c.selector.substr(5), names)));
      continue;
    }
    if (c.kind == Call::Kind::Sum) {
      // The attribute must be one of the selected objects' types (checked on the types, as a
      // variant may select other objects).
      bool known = false;
      for (const ObjectType& t : wc.types) known |= t.find_attribute(c.attribute) >= 0;
      known |= c.attribute == "location.x" || c.attribute == "location.y" || c.attribute == "location.z";
      if (!known)
        diag.error(where(c.position), fmt::format("metric '{}': no type has an attribute '{}'", spec_.name, c.attribute));
    }
  }
  for (const std::string& name : expr_->names()) {
    if (name.starts_with("_call")) continue;
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

double Metric::evaluate(const Workcell& wc, const CheckReport& report, const RunSummary* run, std::string* error) const {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  auto call_value = [&](const Call& c) -> double {
    switch (c.kind) {
      case Call::Kind::MinMargin:
      case Call::Kind::Margin: {
        double best = kNaN;
        for (const CheckResult& r : report.results) {
          if (!r.margin || !std::isfinite(*r.margin)) continue;
          if (c.kind == Call::Kind::Margin && wc.constraints[r.constraint].name != c.constraint) continue;
          best = std::isnan(best) ? *r.margin : std::min(best, *r.margin);
        }
        return best;
      }
      case Call::Kind::Count:
      case Call::Kind::Sum: {
        auto objects = wc.select(c.selector);
        if (!objects) return c.kind == Call::Kind::Count ? 0.0 : kNaN;  // a name this variant lacks selects nothing
        if (c.kind == Call::Kind::Count) return static_cast<double>(objects->size());
        double total = 0;
        for (int o : *objects) {
          const Object& obj = wc.objects[o];
          if (c.attribute.starts_with("location.")) {
            total += wc.values[obj.first_slot + kLocationSlot + (c.attribute.back() - 'x')];
            continue;
          }
          const ObjectType& t = wc.types[obj.type];
          int a = t.find_attribute(c.attribute);
          if (a < 0) {
            *error = fmt::format("metric '{}': {} ({}) has no attribute '{}'", spec_.name, obj.name, t.name, c.attribute);
            return kNaN;
          }
          total += si_to_file(wc.values[obj.first_slot + kFirstAttributeSlot + a], t.attributes[a].dim);
        }
        return total;
      }
    }
    return kNaN;
  };
  std::vector<double> values;
  for (const std::string& name : expr_->names()) {
    if (name.starts_with("_call")) {
      values.push_back(call_value(calls_[std::stoul(name.substr(5))]));
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
      values.push_back(p == wc.parameters.end() ? kNaN : si_to_file(wc.values[p->slot], p->dim));
    }
    if (!error->empty()) return kNaN;
  }
  return expr_->evaluate(values.data());
}

}  // namespace sscs
