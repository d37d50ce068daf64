#include "check/check.h"

#include "geometry/collision.h"
#include "core/selection_calls.h"
#include "kinematics/closest.h"
#include "kinematics/ik.h"

#include <algorithm>
#include <numbers>
#include <set>
#include <cmath>
#include <functional>
#include <limits>

#include <fmt/compile.h>
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

double operand_value(const Operand& op, const std::vector<double>& values, const GeometryModel& geometry) {
  switch (op.kind) {
    case Operand::Kind::Slot: return values[op.slot];
    case Operand::Kind::BoundingBox: return bbox_value(geometry, op.object, op.slot);
    case Operand::Kind::Aggregate: {
      using K = SelectionCall::Kind;
      const std::vector<Operand>& members = *op.members;
      const auto kind = static_cast<K>(op.aggregate);
      if (kind == K::Count) return static_cast<double>(members.size());
      // The min, max or mean of nothing is undefined: NaN, which the check reports as an error.
      if (members.empty()) return kind == K::Sum ? 0.0 : std::numeric_limits<double>::quiet_NaN();
      double total = 0, lo = INFINITY, hi = -INFINITY;
      for (const Operand& m : members) {
        double x = operand_value(m, values, geometry);
        total += x;
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
      return kind == K::Min ? lo : kind == K::Max ? hi : kind == K::Avg ? total / static_cast<double>(members.size()) : total;
    }
    default: return op.constant_si;
  }
}

namespace {

/// What the checker reads: slot values and geometry of one state of the workcell.
struct State {
  const std::vector<double>& values;
  const GeometryModel& geometry;
  bool describe_passes;
  const CheckOptions& options;
};

double read(const Operand& op, const State& st) { return operand_value(op, st.values, st.geometry); }

/// The rounding a difference of values of magnitude `scale` may carry (a few ulps).
double rounding_slack(double scale) { return 8 * std::numeric_limits<double>::epsilon() * std::max(scale, 1e-300); }

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
  // A difference of exactly eps (as written) holds whatever binary rounding made of it.
  const double slack = rounding_slack(std::max({std::abs(L), std::abs(R), b.eps_si}));
  // Sides equal up to rounding are equal: `0.1 + 0.2 > 0.3` fails with margin 0, as in `expr`.
  auto snap = [&](double m) { return std::abs(m) <= slack ? 0.0 : m; };
  switch (b.op) {
    case RelOp::LT: margin = snap(R - L); pass = margin > 0; break;
    case RelOp::LE: margin = snap(R - L); pass = margin >= -b.eps_si - slack; break;
    case RelOp::GT: margin = snap(L - R); pass = margin > 0; break;
    case RelOp::GE: margin = snap(L - R); pass = margin >= -b.eps_si - slack; break;
    case RelOp::EQ: margin = snap(b.eps_si - std::abs(L - R)); pass = margin >= -slack; break;
  }
  r.dim = b.dim;
  r.lhs = si_to_file(lhs, b.dim);
  r.rhs = si_to_file(rhs, b.dim);
  r.margin = si_to_file(margin, b.dim);
  r.status = pass ? Status::Pass : Status::Fail;
  if (pass && !values.describe_passes) return;
  // Written straight into the message (a JSON report describes every pass: 100,000 of them).
  const char* unit = file_unit(b.dim);
  const char* space = *unit ? " " : "";
  std::string& m = r.message;
  m.clear();
  auto out = std::back_inserter(m);
  auto side = [&](const Operand& op, double value, double tol) {
    if (op.kind != Operand::Kind::Constant) fmt::format_to(out, FMT_COMPILE("{} = "), op.text);
    fmt::format_to(out, FMT_COMPILE("{:g}{}{}"), si_to_file(value, b.dim), space, unit);
    if (tol != 0) fmt::format_to(out, FMT_COMPILE(" {} {:g}{}{}"), tol < 0 ? '-' : '+', si_to_file(std::abs(tol), b.dim), space, unit);
  };
  side(b.lhs, lhs, b.lhs_tol_si);
  fmt::format_to(out, FMT_COMPILE(" {} "), relop_symbol(b.op));
  side(b.rhs, rhs, b.rhs_tol_si);
  m += pass ? ": holds" : ": violated";
}

double evaluate(const Expression& e, const std::vector<Operand>& inputs, const State& values,
                std::vector<double>& scratch) {
  scratch.resize(inputs.size());
  for (size_t i = 0; i < inputs.size(); ++i) scratch[i] = read(inputs[i], values);
  return e.evaluate(scratch.data());
}

/// A comparison's margin and verdict. Sides equal up to rounding are equal: a margin within a few
/// ulps of the largest value either side read (`0.1 + 0.2 <= 0.3` holds, `0.1 + 0.2 < 0.3` does not).
struct ExprVerdict {
  double margin;
  bool pass;
  bool defined = true;  ///< false when a side of a comparison is infinite or not a number
};

double largest_magnitude(const std::vector<double>& values, double start) {
  for (double v : values) start = std::max(start, std::abs(v));
  return start;
}

ExprVerdict margin_of(const ExprCheck::MarginNode& n, const State& values, std::vector<double>& scratch,
                      double* lhs, double* rhs) {
  switch (n.op) {
    case MarginTree::Op::And:
    case MarginTree::Op::Or: {
      const bool all = n.op == MarginTree::Op::And;
      ExprVerdict v{all ? INFINITY : -INFINITY, all};
      for (const auto& c : n.children) {
        ExprVerdict cv = margin_of(c, values, scratch, nullptr, nullptr);
        v.margin = all ? std::min(v.margin, cv.margin) : std::max(v.margin, cv.margin);
        v.pass = all ? v.pass && cv.pass : v.pass || cv.pass;
        v.defined = v.defined && cv.defined;
      }
      return v;
    }
    case MarginTree::Op::Not: {  // `!(A)`: A's verdict turned over, its margin negated
      ExprVerdict cv = margin_of(n.children[0], values, scratch, nullptr, nullptr);
      return {-cv.margin, !cv.pass, cv.defined};
    }
    default: break;
  }
  double L = evaluate(*n.lhs.expr, n.lhs.inputs, values, scratch);
  double scale = largest_magnitude(scratch, std::abs(L));
  double R = evaluate(*n.rhs.expr, n.rhs.inputs, values, scratch);
  scale = largest_magnitude(scratch, std::max(scale, std::abs(R)));
  if (lhs) *lhs = L;
  if (rhs) *rhs = R;
  if (!std::isfinite(L) || !std::isfinite(R)) return {NAN, false, false};  // `x / 0 > 1`, `0/0 == 0/0`
  double m = NAN;
  switch (n.op) {
    case MarginTree::Op::Lt:
    case MarginTree::Op::Le: m = R - L; break;
    case MarginTree::Op::Gt:
    case MarginTree::Op::Ge: m = L - R; break;
    case MarginTree::Op::Eq: m = -std::abs(L - R); break;
    case MarginTree::Op::Ne: m = std::abs(L - R); break;
    default: return {NAN, false};
  }
  if (std::abs(m) <= rounding_slack(scale) * static_cast<double>(std::max<size_t>(1, n.lhs.inputs.size() + n.rhs.inputs.size())))
    m = 0;
  const bool strict = n.op == MarginTree::Op::Lt || n.op == MarginTree::Op::Gt || n.op == MarginTree::Op::Ne;
  return {m, strict ? m > 0 : m >= 0};
}

/// " (A.x = 1, B.y = 2)": the values an expression read, for its message ("" when only constants).
std::string input_values(const ExprCheck& e, const State& values) {
  std::vector<std::string> parts;
  for (const Operand& in : e.inputs)
    if (in.kind != Operand::Kind::Constant) {
      // As written in the file: in its unit (30 deg, not 0.523599).
      const char* unit = file_unit(in.dim);
      parts.push_back(fmt::format("{} = {:g}{}{}", in.text, stable(si_to_file(read(in, values), in.dim)), *unit ? " " : "", unit));
    }
  return parts.empty() ? "" : fmt::format(" ({})", fmt::join(parts, ", "));
}

void check_expr(const ExprCheck& e, const State& values, CheckResult& r) {
  std::vector<double> scratch;
  double v = evaluate(*e.expr, e.inputs, values, scratch);
  // An input that is not a number (the min, max or mean of nothing; a size of no geometry) makes
  // the result undefined even where a comparison with NaN would say "false": an error.
  for (size_t i = 0; i < e.inputs.size(); ++i)
    if (std::isnan(scratch[i])) {  // evaluate() read the inputs into scratch
      r.status = Status::Error;
      r.message = fmt::format("'{}' could not be evaluated: {} is not a number", e.text, e.inputs[i].text);
      return;
    }
  if (!std::isfinite(v)) {
    r.status = Status::Error;
    r.message = fmt::format("'{}' could not be evaluated ({})", e.text, std::isnan(v) ? "not a number" : "infinite");
    return;
  }
  bool pass = v != 0;
  r.status = pass ? Status::Pass : Status::Fail;
  if (e.margin) {
    double lhs = NAN, rhs = NAN;
    ExprVerdict verdict = margin_of(*e.margin, values, scratch, &lhs, &rhs);
    if (!verdict.defined) {  // a comparison of a value that is no number has no verdict
      r.status = Status::Error;
      r.message = fmt::format("'{}' could not be evaluated: a side of a comparison is infinite or not a number{}", e.text,
                              input_values(e, values));
      return;
    }
    // The verdict with rounding slack: muparser's own comparison has none.
    pass = verdict.pass;
    r.status = pass ? Status::Pass : Status::Fail;
    // In the file unit of what the sides compare (a yaw margin in deg, as the yaw is written).
    const Dim dim = e.margin->dim;
    r.dim = dim;
    double m = si_to_file(verdict.margin, dim);
    if (std::isfinite(m)) r.margin = m == 0 ? 0.0 : m;  // never -0
    if (e.margin->op != MarginTree::Op::And && e.margin->op != MarginTree::Op::Or && e.margin->op != MarginTree::Op::Not) {
      r.lhs = si_to_file(lhs, dim);
      r.rhs = si_to_file(rhs, dim);
    }
  }
  if (pass && !values.describe_passes) return;
  r.message = fmt::format("{}: {}{}", e.text, pass ? "holds" : "violated", input_values(e, values));
}

constexpr double kTouch = kTouchTolerance;  // touching within this is not overlap

/// A spatial margin within `eps` of the limit is the limit: a clearance of exactly its minimum, or
/// an object flush with its container's face, holds although rounding left it at -4e-16.
/// Distances come from GJK run to a tolerance of 1e-9 m: a margin of exactly eps is met within it.
constexpr double kDistanceAccuracy = 2e-9;
double at_limit(double margin, double eps) {
  return std::abs(margin) <= eps + kDistanceAccuracy + rounding_slack(std::max(eps, std::abs(margin))) ? 0.0 : margin;
}

std::string pair_text(const Workcell& wc, int a, int b) {
  return fmt::format("{} and {}", wc.objects[a].name, wc.objects[b].name);
}

/// clearance, no_overlap and inside: failing members one result each; when none fails, one
/// passing result with the smallest margin seen. Comparisons hold within the constraint's eps or
/// `tolerance`, whichever is larger.
void check_spatial(const Workcell& wc, const SpatialCheck& sc, const GeometryModel& geometry, CollisionWorld& world,
                   double tolerance, int index, std::vector<CheckResult>& out) {
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
  const double eps = std::max(sc.eps_si, tolerance);
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
      // Every pair across the two sides (each a single object, or a selector).
      std::set<std::pair<int, int>> seen;
      for (int a : sc.objects)
        for (int b : sc.others) {
          if (a == b || !seen.insert({std::min(a, b), std::max(a, b)}).second) continue;
          // Selectors on either side: like a set, an object is not checked against its own
          // room (an ancestor or descendant); a pair named one by one is checked as asked.
          if (sc.objects.size() * sc.others.size() > 1 && wc.nested(a, b)) continue;
          auto d = world.distance(a, b);
          if (!d) {
            result({a, b}, Status::Error, {}, {}, {}, fmt::format("{}: one of them has no geometry", pair_text(wc, a, b)));
            continue;
          }
          double margin = at_limit(*d - sc.min_si, eps);
          note(margin, a, b);
          if (margin < 0 || sc.objects.size() * sc.others.size() == 1)
            result({a, b}, margin >= 0 ? Status::Pass : Status::Fail, *d, sc.min_si, margin,
                   fmt::format("distance between {} is {:g} m, min {:g} m", pair_text(wc, a, b), stable(*d), stable(sc.min_si)));
        }
      if (sc.objects.size() * sc.others.size() == 1) return;
      break;
    }
    case SpatialCheck::Kind::ClearanceSet:
    case SpatialCheck::Kind::NoOverlap: {
      bool overlap = sc.kind == SpatialCheck::Kind::NoOverlap;
      double min = overlap ? 0.0 : sc.min_si;
      const double tol = overlap ? std::max(kTouch, eps) : eps;
      std::set<std::pair<int, int>> measured;
      for (auto [a, b] : world.candidate_pairs(sc.objects, overlap ? kTouch : sc.min_si)) {
        if (wc.nested(a, b)) continue;  // a rack stands inside its room
        measured.insert({a, b});
        auto d = world.distance(a, b);
        if (!d) continue;
        double margin = at_limit(*d - min, tol);
        note(margin, a, b);
        bool fails = margin < 0;
        if (!fails) continue;
        if (overlap)
          result({a, b}, Status::Fail, *d, 0.0, *d,
                 fmt::format("{} overlap by {:g} m", pair_text(wc, a, b), stable(-*d)));
        else
          result({a, b}, Status::Fail, *d, min, margin,
                 fmt::format("distance between {} is {:g} m, min {:g} m", pair_text(wc, a, b), stable(*d), stable(min)));
      }
      // A passing set's margin is that of its nearest pair over every pair, not only of those the
      // limit's broadphase met (a pair of turned boxes whose bounds touch may be farther apart
      // than one whose bounds do not; a set with no pair within reach had no margin). Any pair
      // nearer than the nearest measured has bounds nearer than it: one more broadphase at that
      // distance finds them all; with none measured, the reach grows until a pair is met.
      if (out.size() == first) {
        double reach = smallest ? *smallest + min : std::max(min, 0.1);
        for (int round = 0; round < 40; ++round) {
          for (auto [a, b] : world.candidate_pairs(sc.objects, reach)) {
            if (wc.nested(a, b) || !measured.insert({a, b}).second) continue;
            if (auto d = world.distance(a, b)) note(at_limit(*d - min, tol), a, b);
          }
          if (smallest && *smallest + min <= reach) break;
          reach = smallest ? *smallest + min : reach * 4;
          if (!smallest && reach > 4 * kMaxLengthSi) break;  // one object, or none apart from their rooms
        }
      }
      // A device in the set must not collide with itself: its non-adjacent parts.
      if (overlap)
        for (int o : sc.objects) {
          if (!geometry.objects[o].device) continue;
          const Device& dev = *geometry.objects[o].device;
          for (const Collision& c : world.self_collisions(o))
            result({o}, Status::Fail, -c.depth, 0.0, -c.depth,
                   fmt::format("{}: parts {} and {} overlap by {:g} m (self-collision)", wc.objects[o].name,
                               dev.parts[c.part].name, dev.parts[c.other_part].name, stable(c.depth)));
        }
      break;
    }
    case SpatialCheck::Kind::Inside: {
      if (sc.container < 0) return;
      for (int o : sc.objects) {
        std::string why;
        auto m = inside_margin(geometry, o, sc.container, &why, sc.faces, sc.min_si);
        if (!m) {
          result({o, sc.container}, Status::Error, {}, {}, {}, fmt::format("{} in {}: {}", wc.objects[o].name,
                                                                            wc.objects[sc.container].name, why));
          continue;
        }
        double margin = at_limit(*m, eps);
        note(margin, o, sc.container);
        if (margin >= 0) continue;
        // Sticking out (through any face) or only too near a counted face? The margin counts `min` too.
        std::string through;
        double out_by = -inside_margin(geometry, o, sc.container, &why, SpatialCheck::All, 0, &through).value_or(0);
        result({o, sc.container}, Status::Fail, {}, {}, margin,
               out_by > eps
                   ? fmt::format("{} sticks out of {} by {:g} m{}{}", wc.objects[o].name, wc.objects[sc.container].name, stable(out_by),
                                 through.empty() ? "" : " through " + through,
                                 sc.min_si > 0 ? fmt::format(" (min {:g} m inside: margin {:g} m)", stable(sc.min_si), stable(margin)) : "")
                   : fmt::format("{} is {:g} m from a face of {}, min {:g} m", wc.objects[o].name, stable(sc.min_si + margin),
                                 wc.objects[sc.container].name, stable(sc.min_si)));
      }
      break;
    }
  }
  if (out.size() > first) return;
  // Nothing failed: one passing result for the whole set.
  std::vector<int> subjects = sc.objects;
  subjects.insert(subjects.end(), sc.others.begin(), sc.others.end());
  if (sc.container >= 0) subjects.push_back(sc.container);
  std::sort(subjects.begin(), subjects.end());
  subjects.erase(std::unique(subjects.begin(), subjects.end()), subjects.end());
  std::string where = closest ? fmt::format("; closest: {}", pair_text(wc, closest->first, closest->second)) : "";
  const size_t n = subjects.size() - (sc.container >= 0 ? 1 : 0);
  result(subjects, Status::Pass, {}, {}, smallest,
         fmt::format("{} object{} checked{}", n, n == 1 ? "" : "s",
                     smallest ? where : (sc.kind == SpatialCheck::Kind::Inside ? "" : "; no pair within reach of the limit")));
}

/// Collision::other of a part that goes below the floor, in reach.

std::string collision_text(const Workcell& wc, const GeometryModel& geometry, int device, const Collision& c) {
  const Device& d = *geometry.objects[device].device;
  if (c.load >= 0) {  // what the tool holds
    const std::string load = wc.objects[c.load].name + " (carried)";
    if (c.other == kFloorObject)
      return c.other_part < 0 ? fmt::format("{} goes {:g} m below the floor", load, stable(c.depth))
                              : fmt::format("{} goes {:g} m into the floor of {}", load, stable(c.depth), wc.objects[c.other_part].name);
    std::string other = wc.objects[c.other].name;
    if (c.other_part >= 0 && geometry.objects[c.other].device) other += "." + geometry.objects[c.other].device->parts[c.other_part].name;
    return fmt::format("{} hits {} by {:g} m", load, other, stable(c.depth));
  }
  if (c.other == kFloorObject)
    return c.other_part < 0 ? fmt::format("part {} goes {:g} m below the floor", d.parts[c.part].name, stable(c.depth))
                            : fmt::format("part {} goes {:g} m into the floor of {}", d.parts[c.part].name, stable(c.depth),
                                          wc.objects[c.other_part].name);
  if (c.other < 0)
    return fmt::format("parts {} and {} collide by {:g} m", d.parts[c.part].name, d.parts[c.other_part].name, stable(c.depth));
  std::string other = wc.objects[c.other].name;
  if (c.other_part >= 0 && geometry.objects[c.other].device)
    other += "." + geometry.objects[c.other].device->parts[c.other_part].name;
  return fmt::format("part {} hits {} by {:g} m", d.parts[c.part].name, other, stable(c.depth));
}

/// The world pose of a reach target.
Eigen::Isometry3d target_pose(const ReachCheck::Target& t, const GeometryModel& geometry) {
  if (t.object < 0) return t.pose;
  return geometry.objects[t.object].frame_pose(t.frame);
}

/// Position-only solutions that all collide may hide a free one in another tool orientation (an
/// arm reaching over a crate rather than into it): try full poses with the tool's z axis along
/// sampled approach directions, from above first, each at four rolls. Returns `rejected` when
/// none is free.
IkResult reach_by_approach(const Chain& chain, const Eigen::Isometry3d& target, const Eigen::VectorXd& seed,
                           const IkOptions& base, const std::function<bool(const Eigen::VectorXd&)>& accept,
                           const IkResult& rejected) {
  static const std::vector<Eigen::Vector3d> kApproach = [] {
    std::vector<Eigen::Vector3d> dirs = {{0, 0, -1}};
    for (double z : {-1.0, 0.0, 1.0})
      for (int k = 0; k < 8; ++k) {
        double a = k * std::numbers::pi / 4;
        dirs.push_back(Eigen::Vector3d(std::cos(a), std::sin(a), z).normalized());
      }
    dirs.push_back({0, 0, 1});
    return dirs;
  }();
  IkOptions opt = base;
  opt.orientation = true;
  opt.angle_tol = 1e-3;
  opt.max_attempts = 8;
  for (const Eigen::Vector3d& z : kApproach) {
    Eigen::Vector3d x = std::abs(z.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    x = (x - z * z.dot(x)).normalized();
    for (int roll = 0; roll < 4; ++roll) {
      Eigen::Isometry3d X = target;
      Eigen::Matrix3d R;
      R.col(0) = x;
      R.col(1) = z.cross(x);
      R.col(2) = z;
      X.linear() = R * Eigen::AngleAxisd(roll * std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      IkResult r = solve_ik(chain, X, seed, opt, accept);
      if (r.ok()) {
        r.angle_error = 0;  // the orientation was free
        return r;
      }
    }
  }
  return rejected;
}

/// With a free orientation, every solution found collides: the sampled approach directions may
/// straddle a narrow free turn (a forklift's pallet clear of an upright only turned by 8 deg,
/// where the collision is as deep at every other turn: no slope to follow). From the least deep
/// collision found (`from`), the tool is turned about each of its axes in 1-degree steps, the
/// nearest turns first, the position held, until a solution `accept` takes.
IkResult reach_by_turning(const Chain& chain, const Eigen::Isometry3d& target, const Eigen::VectorXd& from, const IkOptions& base,
                          const std::function<bool(const Eigen::VectorXd&)>& accept, const IkResult& rejected) {
  IkOptions opt = base;
  opt.orientation = true;
  opt.angle_tol = 1e-3;
  opt.max_attempts = 2;
  const Eigen::Matrix3d R0 = chain.forward(from).linear();
  for (int deg = 1; deg <= 180; ++deg)
    for (int axis = 0; axis < 3; ++axis)
      for (int sign : {1, -1}) {
        if (deg == 180 && sign < 0) continue;
        Eigen::Isometry3d X = target;
        X.linear() = R0 * Eigen::AngleAxisd(sign * deg * kRadPerDeg, Eigen::Vector3d::Unit(axis)).toRotationMatrix();
        IkResult r = solve_ik(chain, X, from, opt, accept);
        if (!r.ok()) continue;
        r.angle_error = 0;  // the orientation was free
        return r;
      }
  return rejected;
}

/// reach: inverse kinematics for every target from the instance's joint values; a solution
/// must be within limits and collision-free. Failing targets one result each, else one pass.
void check_reach(const Workcell& wc, const ReachCheck& rc, const State& st, CollisionWorld& world, int index,
                 std::vector<CheckResult>& out) {
  if (rc.device < 0) return;
  const ObjectGeometry& g = st.geometry.objects[rc.device];
  const Device& d = *g.device;
  const Object& o = wc.objects[rc.device];
  const Chain chain(d);
  const Eigen::VectorXd q0 = d.joint_values(&st.values[o.first_slot + kFirstAttributeSlot]);
  const Eigen::VectorXd seed = chain.from_device(q0);
  const Eigen::Isometry3d X_root_world = g.X_world_object.inverse();
  IkOptions opt;
  opt.orientation = rc.match_orientation;
  opt.position_tol = rc.position_tol_si;
  opt.angle_tol = rc.angle_tol_si;
  opt.iterations_per_attempt = 60;
  opt.max_attempts = 100;
  // No clock: the attempts and iterations alone end a search, so its verdict is the same on a
  // loaded machine, in a sweep that remembers collision answers, and alone (a 2 s backstop once
  // turned a slow `fail` into an `error` there, and not here).
  opt.time_limit = INFINITY;
  // Containers are spaces, what the device stands on its base may touch, its tool may touch the
  // target, no moving part goes into the floors: as the planner and a run judge it.
  const DeviceClearance clearance(wc, st.geometry, rc.device);
  // The parts no joint of the chain moves stand where they stand for every candidate: when one
  // of them collides, no candidate is free, and a search would only find that 100 times over.
  std::vector<char> unmoved(d.parts.size(), 0);
  {
    std::vector<char> chain_joint(d.dof(), 0), moves(d.parts.size(), 0);
    for (int k = 0; k < chain.size(); ++k) chain_joint[chain.device_index(k)] = 1;
    for (size_t p = 0; p < d.parts.size(); ++p) {  // parents come first
      const Part& part = d.parts[p];
      moves[p] = part.parent >= 0 && (moves[part.parent] || (part.joint.q >= 0 && chain_joint[part.joint.q]));
      unmoved[p] = !moves[p];
    }
  }
  const std::vector<char> is_container = containers(wc);
  // `carrying`: the load's origin at the target when the tool is at the target with the offset,
  // so the tool holds it at the offset's inverse; what rides on it keeps its place on it.
  HeldLoad load;
  if (rc.carrying >= 0) {
    const Eigen::Isometry3d X_tool_load = rc.offset.inverse();
    load.objects.emplace_back(rc.carrying, X_tool_load);
    const Eigen::Isometry3d X_load_world = st.geometry.objects[rc.carrying].X_world_object.inverse();
    for (int rider : rc.carried_with) load.objects.emplace_back(rider, X_tool_load * X_load_world * st.geometry.objects[rider].X_world_object);
  }
  size_t first = out.size();
  std::optional<double> smallest;
  std::string closest;
  for (size_t target = 0; target < rc.targets.size(); ++target) {
    if (st.options.cancel && st.options.cancel->load(std::memory_order_relaxed)) throw CheckCancelled{};
    const ReachCheck::Target& t = rc.targets[target];
    Eigen::Isometry3d X_world_target = target_pose(t, st.geometry);
    // The offset places the target in the frame named (with `free`, its position: an offset
    // written there was silently dropped).
    X_world_target = X_world_target * rc.offset;
    // The tool may touch its target, but a point inside the target's solid is reached only by a
    // tool buried in it (it was a pass: the tool's parts may touch the target). Containers (a
    // room, a shipping container: objects that hold others) are spaces, not solids.
    if (t.object >= 0 && !is_container[t.object]) {
      const double depth = world.depth_inside(t.object, X_world_target.translation());
      if (depth > rc.position_tol_si) {
        CheckResult r;
        r.constraint = index;
        r.subjects = {rc.device, t.object};
        r.status = Status::Fail;
        r.dim = Dim::Length;
        r.lhs = depth;
        r.rhs = rc.position_tol_si;
        r.margin = -depth;
        const bool offset = !rc.offset.isApprox(Eigen::Isometry3d::Identity());
        r.message = fmt::format("{}{} lies {:g} m inside the solid of {}: a tool reaches it only buried in the object "
                                "(aim at a frame on its surface, such as top{})",
                                t.text, offset ? " with the offset" : "", stable(depth), wc.objects[t.object].name,
                                offset ? ", with an offset that keeps the point outside" : "");
        out.push_back(std::move(r));
        continue;
      }
    }
    // A candidate is rejected at its first collision (its depth a lower bound: exact mesh depths
    // cost seconds a target); the one reported is measured exactly once the search is over.
    std::optional<Collision> hit;
    Eigen::VectorXd hit_q;
    auto collision_at = [&](const Eigen::VectorXd& chain_q, bool first) {
      // (A target's searches try thousands of poses: a newer save stops them here too.)
      if (st.options.cancel && st.options.cancel->load(std::memory_order_relaxed)) throw CheckCancelled{};
      Eigen::VectorXd q = q0;
      chain.to_device(chain_q, q);
      return clearance.at(world, q, t.object, first, {}, load);
    };
    auto accept = [&](const Eigen::VectorXd& chain_q) {
      auto c = collision_at(chain_q, true);
      if (c && (!hit || c->depth < hit->depth)) {
        hit = c;
        hit_q = chain_q;
      }
      return !c;
    };
    IkResult ik;
    const std::optional<Collision> stuck = clearance.of_parts(world, q0, t.object, unmoved, load);
    if (stuck) {
      // Reached or not within the joint limits decides the message; every pose that reaches it
      // has this collision.
      ik = solve_ik(chain, X_root_world * X_world_target, seed, opt);
      if (ik.ok()) {
        ik.status = IkResult::Status::Rejected;
        hit = stuck;
      }
    } else {
      ik = solve_ik(chain, X_root_world * X_world_target, seed, opt, accept);
      if (ik.status == IkResult::Status::Rejected && !rc.match_orientation)
        ik = reach_by_approach(chain, X_root_world * X_world_target, seed, opt, accept, ik);
      if (ik.status == IkResult::Status::Rejected && !rc.match_orientation && hit)
        ik = reach_by_turning(chain, X_root_world * X_world_target, hit_q, opt, accept, ik);
      if (ik.status == IkResult::Status::Rejected && hit) hit = collision_at(hit_q, false);
    }
    // Not reached: the margin is minus the closest the device comes, over every configuration
    // within its limits free of collision (vault-format.md), found by a global search, not where
    // the solver stopped (mirror-image targets differed by 0.8 m, a crane's hook clamped 2 m
    // off read 2.00015). The search may also find the target reached after all.
    bool beyond = false, no_free_pose = false;
    std::string closest_collides;  // what the closest pose hits, when no free pose was measured
    std::optional<double> nearer_in_collision;  // a pose in collision comes this close (a device that turns)
    const Eigen::Isometry3d X_root_target = X_root_world * X_world_target;
    // (When a part no joint moves collides, every pose does: the collision says nothing of how
    // close the tool comes, and no pose is free to measure it at.)
    auto free = [&](const Eigen::VectorXd& q) { return !collision_at(q, true); };
    // A device of slides alone (gantry, crane) has a search for the closest free pose that
    // moves one axis at a time from free starts and rays from the closest pose; a device that
    // turns has not (that search stalls in the valleys its coupled joints make).
    bool slides = true;
    for (int k = 0; k < chain.size(); ++k) slides = slides && !chain.revolute(k);
    // Reached only in collision: the margin is minus the closest a free pose comes (the spec's
    // figure), for slides; it was the depth of the shallowest collision, which no move fixes (a
    // drum 0.086 m into one beam of a gap 0.122 m too narrow for it).
    std::optional<double> free_error;
    Eigen::VectorXd free_q;  // the pose free_error is measured at
    // A device that turns too (review 22: an arm carrying a drum over a pedestal read -0.286, the
    // drum's depth into it, where the closest free pose is 0.742 m off): its search through free
    // poses is local, so the figure is a bound the truth is no worse than, and the message says so.
    // (Its starts alone: the rays out of the colliding pose found the tutorial's crate 1.8 cm off
    // where the starts find 3.6 cm, at six times the cost a failing target: a sweep of the demo
    // vault's crowded variants took 1 s a variant.)
    if (ik.status == IkResult::Status::Rejected && !stuck) {
      const ClosestReach closest = closest_free(chain, X_root_target, rc.match_orientation, hit ? hit_q : ik.q, free, /*rays=*/slides);
      if (closest.found && closest.position_error <= rc.position_tol_si && closest.angle_error <= rc.angle_tol_si) {
        ik.q = closest.q;  // free after all
        ik.position_error = closest.position_error;
        ik.angle_error = closest.angle_error;
        ik.status = IkResult::Status::Reached;
      } else if (closest.found) {
        free_error = closest.position_error;
        free_q = closest.q;
      }
    }
    if (ik.status == IkResult::Status::Unreachable) {
      beyond = (X_root_target.translation() - chain.base_point()).norm() > chain.reach_bound() + rc.position_tol_si;
      ClosestReach closest = closest_reach(chain, X_root_target, rc.match_orientation, ik.q,
                                           stuck ? std::function<bool(const Eigen::VectorXd&)>() : free);
      // The closest poses of all collide (a carried drum in its neighbour at the end of the
      // travel). For slides: the closest free pose (it said the unconstrained 0.2 m where the
      // free pose is 0.254 m off, by hand). A device that turns: the message says the closest
      // pose collides and the margin is that pose's, better than the truth (an arm read 0.27 m
      // where 0.02 m was likely).
      // (A device that turns did not search, and gave the closest pose's error with what it
      // hits: an arm carrying a drum beside a pedestal read 0.0297 m where the closest free
      // pose is 0.458 m off; review 22. Its search through free poses is local: a bound.)
      bool searched_free = false;
      if (!closest.found && !stuck) {
        closest = closest_free(chain, X_root_target, rc.match_orientation, ik.q, free);
        searched_free = true;
        no_free_pose = !closest.found;
        if (no_free_pose && !slides) {
          if (const ClosestReach any = closest_reach(chain, X_root_target, rc.match_orientation, ik.q); any.found) {
            ik.q = any.q;
            ik.position_error = any.position_error;
            ik.angle_error = any.angle_error;
          }
          if (auto c = collision_at(ik.q, false)) closest_collides = collision_text(wc, st.geometry, rc.device, *c);
        }
      }
      // A device that turns: the global search's closest free pose is its first refined pose
      // free of collision, far when the nearer ones collide (an arm turned away from its target
      // read 2.62 m where a free pose 1.46 m off exists: a review). A pattern search over free
      // poses, from the free starts and that pose, may only bring it closer; and when a pose in
      // collision still comes closer, the message says that a closer free pose may exist.
      if (closest.found && !stuck && !slides) {
        if (!searched_free) {
          const ClosestReach better = closest_free(chain, X_root_target, rc.match_orientation, closest.q, free);
          if (better.found && better.position_error < closest.position_error - 1e-6 &&
              better.angle_error <= std::max(closest.angle_error, rc.angle_tol_si))
            closest = better;
        }
        if (const ClosestReach any = closest_reach(chain, X_root_target, rc.match_orientation, ik.q);
            any.found && any.position_error < closest.position_error - rc.position_tol_si)
          nearer_in_collision = any.position_error;
      }
      if (closest.found) {
        ik.q = closest.q;
        ik.position_error = closest.position_error;
        ik.angle_error = closest.angle_error;
        if (closest.position_error <= rc.position_tol_si && closest.angle_error <= rc.angle_tol_si) ik.status = IkResult::Status::Reached;
      }
    }
    if (ik.ok() && ik.position_error < 1e-9) ik.position_error = 0;  // rounding: keep reports stable
    CheckResult r;
    r.constraint = index;
    r.subjects = {rc.device};
    if (t.object >= 0) r.subjects.push_back(t.object);
    if (rc.carrying >= 0) r.subjects.push_back(rc.carrying);
    r.dim = Dim::Length;
    r.lhs = ik.position_error;
    r.rhs = rc.position_tol_si;
    std::string angle = rc.match_orientation ? fmt::format(", angle error {:g} deg", stable(si_to_file(ik.angle_error, Dim::Angle))) : "";
    switch (ik.status) {
      case IkResult::Status::Reached: {
        if (st.options.on_reach_solution) {
          Eigen::VectorXd q = q0;
          chain.to_device(ik.q, q);
          st.options.on_reach_solution(index, static_cast<int>(target), q);
        }
        double margin = rc.position_tol_si - ik.position_error;
        if (!smallest || margin < *smallest) {
          smallest = margin;
          closest = t.text;
        }
        continue;
      }
      case IkResult::Status::Unreachable:
        r.status = Status::Fail;
        r.margin = -ik.position_error;
        r.message = beyond ? fmt::format("{} cannot reach {}: it lies beyond the device's reach; the closest its tool comes is {:g} m{}",
                                         o.name, t.text, stable(ik.position_error), angle)
                           : fmt::format("{} cannot reach {} within its joint limits: the closest its tool comes is {:g} m{}", o.name,
                                         t.text, stable(ik.position_error), angle);
        if (no_free_pose) r.message += " (every pose the search tried near it collides: the closest free pose may be farther)";
        if (nearer_in_collision && ik.status == IkResult::Status::Unreachable)
          r.message += fmt::format(" (the closest free of collision that the search found; a pose in collision comes within {:g} m, "
                                   "and a free pose between may exist)", stable(*nearer_in_collision));
        if (!closest_collides.empty())
          r.message += fmt::format(" (in collision there: {}; a pose free of collision comes no closer, and how much farther it "
                                   "is was not measured)", closest_collides);
        break;
      case IkResult::Status::Rejected:
        r.status = Status::Fail;
        r.margin = free_error ? -*free_error : hit ? -hit->depth : 0.0;
        if (free_error) r.lhs = *free_error;
        if (hit && hit->other >= 0 && hit->other == t.object && hit->part >= 0 && d.tool_parts()[hit->part])
          r.message = fmt::format("{} reaches {} only with its tool inside {}: part {} enters it by {:g} m (a tool may touch its "
                                  "target, by {:g} mm at most)", o.name, t.text, wc.objects[t.object].name, d.parts[hit->part].name,
                                  stable(hit->depth), kTargetTouch * 1000);
        else
          r.message = fmt::format("{} reaches {} only in collision: {}", o.name, t.text,
                                  hit ? collision_text(wc, st.geometry, rc.device, *hit) : "?");
        if (free_error)
          r.message += fmt::format("; the closest a pose free of collision comes is {:g} m{}", stable(*free_error),
                                   slides ? "" : " (the closest the search found: a closer free pose may exist)");
        // The subjects stay the device, the target and the load: a baseline matches results by
        // them, and what a pose hits changes with the design (it is in the message).
        break;
    }
    {
      auto pose = std::make_shared<ClosestPose>();
      Eigen::VectorXd q = q0;
      // Reached only in collision: the closest free pose when one was measured (the result's
      // value), else the pose that reaches it and collides.
      const bool rejected = ik.status == IkResult::Status::Rejected;
      chain.to_device(rejected && free_error ? free_q : rejected && hit_q.size() == chain.size() ? hit_q : ik.q, q);
      for (int k = 0; k < d.dof(); ++k) pose->joints.push_back({d.joint(k).name, d.joint(k).type == JointType::Revolute, q[k]});
      const std::vector<Eigen::Isometry3d> X = d.part_poses(q);
      for (size_t p = 0; p < d.parts.size(); ++p) pose->parts.push_back({d.parts[p].name, X[p]});
      pose->tool = g.X_world_object * d.tool_pose(q).translation();
      pose->target = X_world_target.translation();
      r.closest = std::move(pose);
    }
    out.push_back(std::move(r));
  }
  if (out.size() > first) return;
  CheckResult r;
  r.constraint = index;
  r.subjects = {rc.device};
  for (const auto& t : rc.targets)
    if (t.object >= 0) r.subjects.push_back(t.object);
  if (rc.carrying >= 0) r.subjects.push_back(rc.carrying);
  std::sort(r.subjects.begin(), r.subjects.end());
  r.subjects.erase(std::unique(r.subjects.begin(), r.subjects.end()), r.subjects.end());
  r.status = Status::Pass;
  r.dim = Dim::Length;
  r.margin = smallest;
  if (st.describe_passes)
    r.message = fmt::format("{} reaches {}{}{}", o.name,
                            rc.targets.size() == 1 ? std::string("its target") : fmt::format("all {} targets", rc.targets.size()),
                            rc.carrying >= 0 ? " carrying " + wc.objects[rc.carrying].name : "",
                            smallest ? fmt::format("; closest to its tolerance: {}", closest) : "");
  out.push_back(std::move(r));
}

/// A plugin's class over the attribute values in their file units; its margin's unit becomes
/// the result's dimension.
void check_plugin(const Constraint& c, const PluginCheck& pc, const State& st, CheckResult& r) {
  std::vector<sscs_value> values;
  for (const Operand& op : pc.inputs)
    values.push_back({op.text.c_str(), si_to_file(read(op, st), op.dim), file_unit(op.dim)});
  PluginOutcome out = pc.evaluate(c.name, values);
  r.message = out.message;
  if (!out.ok) {
    r.status = Status::Error;
    return;
  }
  r.status = out.pass ? Status::Pass : Status::Fail;
  r.dim = Dim::None;
  for (Dim d : {Dim::Length, Dim::Angle, Dim::Mass, Dim::Time})
    if (out.unit == file_unit(d)) r.dim = d;
  if (r.dim == Dim::None) r.unit = out.unit;
  r.margin = out.margin;
}

}  // namespace

CheckReport check(const Workcell& wc, const GeometryModel& geometry, const CheckOptions& options) {
  return check(wc, geometry, wc.values, options);
}

CheckReport check(const Workcell& wc, const GeometryModel& geometry, const std::vector<double>& slot_values,
                  const CheckOptions& options) {
  State values{slot_values, geometry, options.describe_passes, options};
  CheckReport report;
  report.results.reserve(wc.constraints.size());
  // Built for the first spatial or reach check (a run re-checks bounds at every step: none).
  std::optional<CollisionWorld> collisions;
  auto world = [&]() -> CollisionWorld& {
    if (!collisions) collisions.emplace(geometry);
    return *collisions;
  };
  for (size_t i = 0; i < wc.constraints.size(); ++i) {
    if (options.cancel && options.cancel->load(std::memory_order_relaxed)) throw CheckCancelled{};
    if (!options.only.empty() && !options.only[i]) continue;
    const Constraint& c = wc.constraints[i];
    auto tally = [&](const CheckResult& r) {
      if (r.status == Status::Pass) ++report.passed;
      else if (r.status == Status::Error) ++report.failed, ++report.unevaluated;
      else if (c.severity == Severity::Warning) ++report.warnings;
      else ++report.failed;
    };
    if (const auto* pc = std::get_if<PluginCheck>(&c.body)) {
      CheckResult r;
      r.constraint = static_cast<int>(i);
      r.subjects = c.subjects;
      check_plugin(c, *pc, values, r);
      tally(r);
      report.results.push_back(std::move(r));
      continue;
    }
    if (const auto* sc = std::get_if<SpatialCheck>(&c.body)) {
      size_t first = report.results.size();
      check_spatial(wc, *sc, geometry, world(), options.spatial_tolerance, static_cast<int>(i), report.results);
      for (size_t k = first; k < report.results.size(); ++k) tally(report.results[k]);
      continue;
    }
    if (const auto* rc = std::get_if<ReachCheck>(&c.body)) {
      size_t first = report.results.size();
      check_reach(wc, *rc, values, world(), static_cast<int>(i), report.results);
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
