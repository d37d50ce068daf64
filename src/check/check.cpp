#include "check/check.h"

#include "geometry/collision.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace sscs {

const char* status_name(Status s) {
  switch (s) {
    case Status::Pass: return "pass";
    case Status::Fail: return "fail";
    case Status::Error: return "error";
  }
  return "?";
}

namespace {

/// What the checker reads: slot values and geometry of one state of the workcell.
struct State {
  const std::vector<double>& values;
  const GeometryModel& geometry;
  bool describe_passes;
};

double read(const Operand& op, const State& st) {
  switch (op.kind) {
    case Operand::Kind::Slot: return st.values[op.slot];
    case Operand::Kind::BoundingBox: return bbox_value(st.geometry, op.object, op.slot);
    default: return op.constant_si;
  }
}

std::string with_unit(double si, Dim dim) {
  const char* unit = file_unit(dim);
  return *unit ? fmt::format("{:g} {}", si_to_file(si, dim), unit) : fmt::format("{:g}", si_to_file(si, dim));
}

void check_bound(const BoundCheck& b, const State& values, CheckResult& r) {
  double lhs = read(b.lhs, values), rhs = read(b.rhs, values);
  if (std::isnan(lhs) || std::isnan(rhs)) {
    r.status = Status::Error;
    r.message = fmt::format("'{}' has no value: the object has no geometry", std::isnan(lhs) ? b.lhs.text : b.rhs.text);
    return;
  }
  double L = lhs + b.lhs_tol_si, R = rhs + b.rhs_tol_si;
  double margin = 0;
  bool pass = false;
  switch (b.op) {
    case RelOp::LT: margin = R - L; pass = margin > 0; break;
    case RelOp::LE: margin = R - L; pass = margin >= -b.eps_si; break;
    case RelOp::GT: margin = L - R; pass = margin > 0; break;
    case RelOp::GE: margin = L - R; pass = margin >= -b.eps_si; break;
    case RelOp::EQ: margin = b.eps_si - std::abs(L - R); pass = margin >= 0; break;
  }
  r.dim = b.dim;
  r.lhs = si_to_file(lhs, b.dim);
  r.rhs = si_to_file(rhs, b.dim);
  r.margin = si_to_file(margin, b.dim);
  r.status = pass ? Status::Pass : Status::Fail;
  if (pass && !values.describe_passes) return;
  auto side = [&](const Operand& op, double value, double tol) {
    std::string s = op.kind != Operand::Kind::Constant ? fmt::format("{} = {}", op.text, with_unit(value, b.dim))
                                                   : with_unit(value, b.dim);
    if (tol != 0) s += fmt::format(" {} {}", tol < 0 ? "-" : "+", with_unit(std::abs(tol), b.dim));
    return s;
  };
  r.message = fmt::format("{} {} {}: {}", side(b.lhs, lhs, b.lhs_tol_si), relop_symbol(b.op), side(b.rhs, rhs, b.rhs_tol_si),
                          pass ? "holds" : "violated");
}

double evaluate(const Expression& e, const std::vector<Operand>& inputs, const State& values,
                std::vector<double>& scratch) {
  scratch.resize(inputs.size());
  for (size_t i = 0; i < inputs.size(); ++i) scratch[i] = read(inputs[i], values);
  return e.evaluate(scratch.data());
}

double margin_of(const ExprCheck::MarginNode& n, const State& values, std::vector<double>& scratch,
                 double* lhs, double* rhs) {
  switch (n.op) {
    case MarginTree::Op::And:
    case MarginTree::Op::Or: {
      double m = n.op == MarginTree::Op::And ? INFINITY : -INFINITY;
      for (const auto& c : n.children) {
        double cm = margin_of(c, values, scratch, nullptr, nullptr);
        m = n.op == MarginTree::Op::And ? std::min(m, cm) : std::max(m, cm);
      }
      return m;
    }
    default: break;
  }
  double L = evaluate(*n.lhs.expr, n.lhs.inputs, values, scratch);
  double R = evaluate(*n.rhs.expr, n.rhs.inputs, values, scratch);
  if (lhs) *lhs = L;
  if (rhs) *rhs = R;
  switch (n.op) {
    case MarginTree::Op::Lt:
    case MarginTree::Op::Le: return R - L;
    case MarginTree::Op::Gt:
    case MarginTree::Op::Ge: return L - R;
    case MarginTree::Op::Eq: return -std::abs(L - R);
    case MarginTree::Op::Ne: return std::abs(L - R);
    default: return NAN;
  }
}

void check_expr(const ExprCheck& e, const State& values, CheckResult& r) {
  std::vector<double> scratch;
  double v = evaluate(*e.expr, e.inputs, values, scratch);
  if (std::isnan(v)) {
    r.status = Status::Error;
    r.message = fmt::format("'{}' could not be evaluated (not a number)", e.expr->text());
    return;
  }
  bool pass = v != 0;
  r.status = pass ? Status::Pass : Status::Fail;
  if (e.margin) {
    double lhs = NAN, rhs = NAN;
    double m = margin_of(*e.margin, values, scratch, &lhs, &rhs);
    if (std::isfinite(m)) r.margin = m;
    if (e.margin->op != MarginTree::Op::And && e.margin->op != MarginTree::Op::Or) {
      r.lhs = lhs;
      r.rhs = rhs;
    }
  }
  if (pass && !values.describe_passes) return;
  std::vector<std::string> parts;
  for (size_t i = 0; i < e.inputs.size(); ++i)
    if (e.inputs[i].kind != Operand::Kind::Constant) parts.push_back(fmt::format("{} = {:g}", e.inputs[i].text, read(e.inputs[i], values)));
  r.message = fmt::format("{}: {}{}", e.expr->text(), pass ? "holds" : "violated",
                          parts.empty() ? "" : fmt::format(" ({})", fmt::join(parts, ", ")));
}

constexpr double kTouch = 1e-6;  // touching within this is not overlap

std::string pair_text(const Workcell& wc, int a, int b) {
  return fmt::format("{} and {}", wc.objects[a].name, wc.objects[b].name);
}

/// clearance, no_overlap and inside: failing members one result each; when none fails, one
/// passing result with the smallest margin seen.
void check_spatial(const Workcell& wc, const SpatialCheck& sc, const GeometryModel& geometry, CollisionWorld& world,
                   int index, std::vector<CheckResult>& out) {
  auto result = [&](std::vector<int> subjects, Status status, std::optional<double> lhs, std::optional<double> rhs,
                    std::optional<double> margin, std::string message) {
    CheckResult r;
    r.constraint = index;
    r.subjects = std::move(subjects);
    r.status = status;
    r.lhs = lhs;
    r.rhs = rhs;
    r.margin = margin;
    r.dim = Dim::Length;
    r.message = std::move(message);
    out.push_back(std::move(r));
  };
  size_t first = out.size();
  std::optional<double> smallest;
  std::optional<std::pair<int, int>> closest;
  auto note = [&](double margin, int a, int b) {
    if (!smallest || margin < *smallest) {
      smallest = margin;
      closest = {a, b};
    }
  };
  switch (sc.kind) {
    case SpatialCheck::Kind::ClearancePair: {
      if (sc.objects.size() != 2) return;
      int a = sc.objects[0], b = sc.objects[1];
      auto d = world.distance(a, b);
      if (!d) {
        result({a, b}, Status::Error, {}, {}, {}, fmt::format("{}: one of them has no geometry", pair_text(wc, a, b)));
        return;
      }
      double margin = *d - sc.min_si;
      result({a, b}, margin >= 0 ? Status::Pass : Status::Fail, *d, sc.min_si, margin,
             fmt::format("distance between {} is {:g} m, min {:g} m", pair_text(wc, a, b), stable(*d), stable(sc.min_si)));
      return;
    }
    case SpatialCheck::Kind::ClearanceSet:
    case SpatialCheck::Kind::NoOverlap: {
      bool overlap = sc.kind == SpatialCheck::Kind::NoOverlap;
      double min = overlap ? 0.0 : sc.min_si;
      for (auto [a, b] : world.candidate_pairs(sc.objects, overlap ? kTouch : sc.min_si)) {
        if (wc.related(a, b)) continue;  // a rack stands inside its room
        auto d = world.distance(a, b);
        if (!d) continue;
        double margin = *d - min;
        note(margin, a, b);
        bool fails = overlap ? *d < -kTouch : margin < 0;
        if (!fails) continue;
        if (overlap)
          result({a, b}, Status::Fail, *d, 0.0, *d,
                 fmt::format("{} overlap by {:g} m", pair_text(wc, a, b), stable(-*d)));
        else
          result({a, b}, Status::Fail, *d, min, margin,
                 fmt::format("distance between {} is {:g} m, min {:g} m", pair_text(wc, a, b), stable(*d), stable(min)));
      }
      break;
    }
    case SpatialCheck::Kind::Inside: {
      if (sc.container < 0) return;
      for (int o : sc.objects) {
        std::string why;
        auto m = inside_margin(geometry, o, sc.container, &why);
        if (!m) {
          result({o, sc.container}, Status::Error, {}, {}, {}, fmt::format("{} in {}: {}", wc.objects[o].name,
                                                                            wc.objects[sc.container].name, why));
          continue;
        }
        note(*m, o, sc.container);
        if (*m < -1e-9)
          result({o, sc.container}, Status::Fail, {}, {}, *m,
                 fmt::format("{} sticks out of {} by {:g} m", wc.objects[o].name, wc.objects[sc.container].name, stable(-*m)));
      }
      break;
    }
  }
  if (out.size() > first) return;
  // Nothing failed: one passing result for the whole set.
  std::vector<int> subjects = sc.objects;
  if (sc.container >= 0) subjects.push_back(sc.container);
  std::sort(subjects.begin(), subjects.end());
  std::string where = closest ? fmt::format("; closest: {}", pair_text(wc, closest->first, closest->second)) : "";
  result(subjects, Status::Pass, {}, {}, smallest,
         fmt::format("{} objects checked{}", sc.objects.size(),
                     smallest ? where : (sc.kind == SpatialCheck::Kind::Inside ? "" : "; no pair within reach of the limit")));
}

}  // namespace

CheckReport check(const Workcell& wc, const GeometryModel& geometry, const CheckOptions& options) {
  return check(wc, geometry, wc.values, options);
}

CheckReport check(const Workcell& wc, const GeometryModel& geometry, const std::vector<double>& slot_values,
                  const CheckOptions& options) {
  State values{slot_values, geometry, options.describe_passes};
  CheckReport report;
  report.results.reserve(wc.constraints.size());
  CollisionWorld world(geometry);
  for (size_t i = 0; i < wc.constraints.size(); ++i) {
    const Constraint& c = wc.constraints[i];
    auto tally = [&](const CheckResult& r) {
      if (r.status == Status::Pass) ++report.passed;
      else if (c.severity == Severity::Warning) ++report.warnings;
      else ++report.failed;
    };
    if (const auto* d = std::get_if<DeferredCheck>(&c.body)) {
      CheckResult r;
      r.constraint = static_cast<int>(i);
      r.status = Status::Error;
      r.subjects = c.subjects;
      r.message = d->reason;
      tally(r);
      report.results.push_back(std::move(r));
      continue;
    }
    if (const auto* sc = std::get_if<SpatialCheck>(&c.body)) {
      size_t first = report.results.size();
      check_spatial(wc, *sc, geometry, world, static_cast<int>(i), report.results);
      for (size_t k = first; k < report.results.size(); ++k) tally(report.results[k]);
      continue;
    }
    CheckResult r;
    r.constraint = static_cast<int>(i);
    r.subjects = c.subjects;
    if (const auto* b = std::get_if<BoundCheck>(&c.body)) check_bound(*b, values, r);
    else if (const auto* e = std::get_if<ExprCheck>(&c.body)) check_expr(*e, values, r);
    tally(r);
    report.results.push_back(std::move(r));
  }
  return report;
}

}  // namespace sscs
