#include "simulate/rechecks.h"

#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <variant>

#include "core/units.h"

#include <fmt/format.h>

namespace sscs {

namespace {

/// Whether an operand reads the motion: a moved object's pose or bounding box, or an attribute
/// of a moved device (its joints), directly or through an aggregate.
bool reads_motion(const Operand& op, const Workcell& wc, const std::set<int>& moving) {
  switch (op.kind) {
    case Operand::Kind::Constant:
      return false;
    case Operand::Kind::Aggregate:
      return op.members && std::any_of(op.members->begin(), op.members->end(), [&](const Operand& m) { return reads_motion(m, wc, moving); });
    case Operand::Kind::BoundingBox:
      return moving.count(op.object) > 0;
    case Operand::Kind::Slot: {
      if (op.object < 0 || !moving.count(op.object)) return false;
      // Its place, or a joint's value: what a device's other attributes say (a forklift's
      // turning_radius) stays as compiled.
      const Object& o = wc.objects[op.object];
      const int attribute = op.slot - o.first_slot - kFirstAttributeSlot;
      if (attribute < 0) return true;
      const ObjectType& type = wc.types[o.type];
      return type.device && attribute < static_cast<int>(type.attributes.size()) && type.attributes[attribute].joint;
    }
  }
  return false;
}

}  // namespace

ConstraintRechecks::ConstraintRechecks(const Workcell& wc, const std::set<int>& moving, double tolerance)
    : wc_(wc), tolerance_(tolerance) {
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
    // Its pairs that move: watched between samples.
    if (only[i] && spatial && (spatial->kind == SpatialCheck::Kind::ClearancePair || spatial->kind == SpatialCheck::Kind::ClearanceSet)) {
      const std::vector<int>& bs = spatial->kind == SpatialCheck::Kind::ClearancePair ? spatial->others : spatial->objects;
      for (int a : spatial->objects)
        for (int b : bs)
          if (a != b && (spatial->kind == SpatialCheck::Kind::ClearancePair || a < b) && (moving.count(a) || moving.count(b)))
            watched_.push_back({static_cast<int>(i), a, b, spatial->min_si});
    }
  }
  // The bounds and expressions among them that read the motion: at every physics step too.
  std::vector<char> step(wc.constraints.size(), 0);
  bool any_step = false;
  for (size_t i = 0; any && i < wc.constraints.size(); ++i) {
    if (!only[i]) continue;
    const Constraint& c = wc.constraints[i];
    if (const auto* b = std::get_if<BoundCheck>(&c.body)) step[i] = reads_motion(b->lhs, wc, moving) || reads_motion(b->rhs, wc, moving);
    else if (const auto* e = std::get_if<ExprCheck>(&c.body))
      step[i] = std::any_of(e->inputs.begin(), e->inputs.end(), [&](const Operand& op) { return reads_motion(op, wc, moving); });
    any_step = any_step || step[i];
  }
  step_options_ = options_;
  motion_options_ = options_;
  std::vector<char> motion(wc.constraints.size(), 0);
  for (size_t i = 0; any && i < wc.constraints.size(); ++i)
    motion[i] = only[i] && (std::holds_alternative<SpatialCheck>(wc.constraints[i].body) || step[i]);
  if (any) motion_options_.only = std::move(motion);
  if (any_step) step_options_.only = std::move(step);
  for (size_t i = 0; any && i < wc.constraints.size(); ++i) {
    const auto* spatial = std::get_if<SpatialCheck>(&wc.constraints[i].body);
    if (!only[i] || !spatial || spatial->kind != SpatialCheck::Kind::Inside || spatial->container < 0) continue;
    Inside in{static_cast<int>(i), spatial->container, spatial->faces, spatial->min_si, std::max(spatial->eps_si, tolerance), {}};
    for (int o : spatial->objects) in.members.push_back({o, {}, {}});
    inside_.push_back(std::move(in));
  }
  if (any) options_.only = std::move(only);
}

void ConstraintRechecks::watch(ClearanceTracker& tracker) const {
  for (const Watched& w : watched_) tracker.watch(w.a, w.b, w.gap - tolerance_);
}

void ConstraintRechecks::check(double t, const GeometryModel& live, const std::vector<double>& values, EventLog& events,
                               const ClearanceTracker* tracker) {
  // Between the samples: a watched pair nearer than its rule's gap, for a rule not failing at
  // the last sample, starts failing at the dip (once a rule and interval, its nearest dip).
  std::set<int> dipped;
  if (tracker) {
    std::map<int, std::pair<const Watched*, ClearanceTracker::Dip>> first;
    for (const Watched& w : watched_) {
      auto d = tracker->dip(w.a, w.b, w.gap - tolerance_, t);
      if (!d || d->t >= t - 1e-9) continue;  // at the sample itself: the check below finds it
      auto it = first.find(w.constraint);
      if (it == first.end() || d->distance - w.gap < it->second.second.distance - it->second.first->gap) first.insert_or_assign(w.constraint, std::make_pair(&w, *d));
    }
    for (const auto& [index, wd] : first) {
      const int ci = index;
      const bool was = std::any_of(failing_.begin(), failing_.end(), [ci](const auto& f) { return f.first.first == ci && f.second; });
      if (was) continue;
      const Watched& w = *wd.first;
      const ClearanceTracker::Dip& d = wd.second;
      const std::string message = fmt::format("{} comes within {:g} m of {} between samples (min {:g} m: margin {:g} m)", d.a,
                                              r9(d.distance), d.b, w.gap, r9(d.distance - w.gap));
      starts_failing(d.t, ci, {w.a, w.b}, d.distance - w.gap, Dim::Length, message, true, events);
      dipped.insert(ci);
    }
  }
  // A clearance rule failing since the last sample or a dip in this interval: its pair's closest
  // approach (certified between samples) is its episode's worst, when it came after the episode
  // began (before the sample may end the episode).
  if (tracker)
    for (const Watched& w : watched_)
      if (const auto closest = tracker->closest_of(w.a, w.b)) worsen(w.constraint, {w.a, w.b}, closest->first - w.gap, closest->second, events);
  const CheckReport report = sscs::check(wc_, live, values, whole_due_ ? options_ : motion_options_);
  whole_due_ = false;
  judge(t, report, dipped, false, events);
  note_inside(report, live);
}

void ConstraintRechecks::check_step(double t, const GeometryModel& live, const std::vector<double>& values, EventLog& events) {
  judge(t, sscs::check(wc_, live, values, step_options_), {}, true, events);
}

std::vector<double> ConstraintRechecks::part_margins(const GeometryModel& live, const Inside& in, int object) {
  const ObjectGeometry& g = live.objects[object];
  const int parts = g.device ? static_cast<int>(g.X_object_part.size()) : 1;
  std::vector<double> out(parts);
  for (int p = 0; p < parts; ++p) {
    std::string why;
    double uncounted = INFINITY;
    const std::optional<double> m = inside_margin(live, object, in.container, &why, in.faces, in.min, nullptr, g.device ? p : -1, &uncounted);
    out[p] = m ? std::min(*m, uncounted) : -INFINITY;
  }
  return out;
}

void ConstraintRechecks::note_inside(const CheckReport& report, const GeometryModel& live) {
  for (Inside& in : inside_) {
    bool seen = false, failing = false;
    for (const CheckResult& r : report.results) {
      if (r.constraint != in.constraint) continue;
      seen = true;
      failing = failing || r.status != Status::Pass;
    }
    if (!seen) continue;
    for (Inside::Member& m : in.members) {
      m.margin = failing ? std::vector<double>() : part_margins(live, in, m.object);
      m.travelled_then.clear();
    }
  }
}

bool ConstraintRechecks::inside_clear(const ClearanceTracker& tracker, const std::map<int, std::vector<double>>& ahead, double* room) const {
  auto most = [](const std::vector<double>* v) { return v && !v->empty() ? *std::max_element(v->begin(), v->end()) : 0.0; };
  auto next = [&](int o) {
    auto it = ahead.find(o);
    return it == ahead.end() ? nullptr : &it->second;
  };
  bool clear = true;
  for (const Inside& in : inside_) {
    if (std::any_of(in.members.begin(), in.members.end(), [](const Inside::Member& m) { return m.margin.empty(); })) continue;
    const double container_gone = most(tracker.travelled(in.container)), container_ahead = most(next(in.container));
    for (const Inside::Member& m : in.members) {
      const std::vector<double>* now = tracker.travelled(m.object);
      const std::vector<double>* more = next(m.object);
      for (size_t p = 0; p < m.margin.size(); ++p) {
        const double gone = (now && p < now->size() ? (*now)[p] : 0.0) - (p < m.travelled_then.size() ? m.travelled_then[p] : 0.0);
        const double going = (more && p < more->size() ? (*more)[p] : 0.0) + container_ahead;
        const double left = m.margin[p] + in.eps - gone - container_gone;
        if (left - going <= 0) {
          clear = false;
          if (room) *room = std::min(*room, going > 0 ? left / going : 0.0);
          if (!room) return false;
        }
      }
    }
  }
  return clear;
}

void ConstraintRechecks::check_inside_step(double t, const ClearanceTracker& tracker, const std::function<void()>& pose,
                                           const GeometryModel& live, const std::vector<double>& values, EventLog& events) {
  // How far any point of `o` may have gone since `then` (per part; empty: since the sample).
  auto went = [&](int o, const std::vector<double>& then) {
    const std::vector<double>* now = tracker.travelled(o);
    double most = 0;
    for (size_t part = 0; now && part < now->size(); ++part) most = std::max(most, (*now)[part] - (part < then.size() ? then[part] : 0.0));
    return most;
  };
  std::vector<char> only;  // the rules to check exactly: allocated only at a step that has one
  for (Inside& in : inside_) {
    if (std::any_of(in.members.begin(), in.members.end(), [](const Inside::Member& m) { return m.margin.empty(); }))
      continue;  // failing at the sample: it cannot start failing
    const double container_went = went(in.container, {});
    for (Inside::Member& m : in.members) {
      // Each part's margin can have shrunk by no more than it and the container went.
      const std::vector<double>* now = tracker.travelled(m.object);
      bool clear = true;
      for (size_t p = 0; p < m.margin.size() && clear; ++p) {
        const double moved = (now && p < now->size() ? (*now)[p] : 0.0) - (p < m.travelled_then.size() ? m.travelled_then[p] : 0.0);
        clear = m.margin[p] + in.eps - moved - container_went > 0;
      }
      if (clear) continue;
      pose();
      m.margin = part_margins(live, in, m.object);
      m.travelled_then = now ? *now : std::vector<double>();
      if (*std::min_element(m.margin.begin(), m.margin.end()) < -in.eps) {  // out: the rule's own check says how
        only.resize(wc_.constraints.size(), 0);
        only[in.constraint] = 1;
      }
    }
  }
  if (only.empty()) return;
  CheckOptions exact = options_;
  exact.only = std::move(only);
  const CheckReport report = sscs::check(wc_, live, values, exact);
  judge(t, report, {}, true, events);
  note_inside(report, live);
}

void ConstraintRechecks::judge(double t, const CheckReport& report, const std::set<int>& already, bool between_samples,
                               EventLog& events) {
  for (const CheckResult& r : report.results) {
    if (std::any_of(r.subjects.begin(), r.subjects.end(), [&](int o) { return absent_.count(o) > 0; })) continue;
    auto key = std::make_pair(r.constraint, r.subjects);
    bool failing = r.status != Status::Pass;
    bool was = failing_[key];
    failing_[key] = failing;
    if (!failing)
      if (auto open = open_.find(episode_key(r.constraint, r.subjects)); open != open_.end()) {
        episodes_[open->second].end = t;
        open_.erase(open);
      }
    if (failing && r.margin) worsen(r.constraint, r.subjects, *r.margin, t, events);
    if (!failing || was || already.count(r.constraint)) continue;  // a dip already started it
    starts_failing(t, r.constraint, r.subjects, r.margin, r.dim, r.message, between_samples, events);
  }
}

void ConstraintRechecks::starts_failing(double t, int constraint, const std::vector<int>& subjects, std::optional<double> margin, Dim dim,
                                        const std::string& message, bool between_samples, EventLog& events) {
  const Constraint& c = wc_.constraints[constraint];
  std::vector<std::string> names;
  for (int o : subjects) names.push_back(wc_.objects[o].name);
  nlohmann::ordered_json f = {{"constraint", c.name}, {"severity", c.severity == Severity::Warning ? "warning" : "error"},
                              {"subjects", names}};
  if (margin) f["margin"] = r9(*margin);
  f["unit"] = file_unit(dim);
  f["message"] = message;
  if (between_samples) f["between_samples"] = true;
  if (margin) {
    f["worst_margin"] = r9(*margin);
    f["worst_at"] = r9(t);
  }
  const size_t event = events.add(t, EventKind::Constraint, f);
  EpisodeKey key = episode_key(constraint, subjects);
  open_[key] = episodes_.size();
  episodes_.push_back({std::move(key), event, t, INFINITY, margin ? *margin : -INFINITY});
  if (c.severity != Severity::Warning) ++failures_;
}

void ConstraintRechecks::worsen(int constraint, const std::vector<int>& subjects, double margin, double t, EventLog& events) {
  const EpisodeKey key = episode_key(constraint, subjects);
  for (Episode& e : episodes_) {
    if (e.key != key || t < e.start - 1e-9 || t > e.end + 1e-9 || !(margin < e.worst)) continue;
    e.worst = margin;
    events.update(e.event, "worst_margin", r9(margin));
    events.update(e.event, "worst_at", r9(t));
  }
}

void ConstraintRechecks::finish(const ClearanceTracker& tracker, EventLog& events) {
  for (const Watched& w : watched_)
    if (const auto closest = tracker.closest_of(w.a, w.b)) worsen(w.constraint, {w.a, w.b}, closest->first - w.gap, closest->second, events);
}

}  // namespace sscs
