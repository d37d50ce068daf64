#include "simulate/clearance.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "model/device.h"
#include "simulate/events.h"

namespace sscs {

namespace {
constexpr double kClearanceReach = 2.0;  // m: clearances beyond this are not tracked
constexpr double kSpanSteps = 1.5 / 64;  // of a physics step: a glide's piece this short is not halved again

/// The least distance of a pair over an interval whose ends are d_i and d_j apart and over which
/// the two went D at most: every point stays within D of where it was at either end, so the
/// distance between is at least the larger of (d_i − x) and (d_j − (D − x)) over x.
double interval_bound(double d_i, double d_j, double D) { return std::min({d_i, d_j, (d_i + d_j - D) / 2}); }
}  // namespace

ClearanceTracker::ClearanceTracker(const Workcell& wc, const GeometryModel& geometry)
    : wc_(wc), geometry_(geometry), nearby_(geometry) {}

std::string run_part_name(const Workcell& wc, const GeometryModel& geometry, int o, int part) {
  if (o < 0) return "floor";
  const ObjectGeometry& g = geometry.objects[o];
  return part >= 0 && g.device ? fmt::format("{}.{}", wc.objects[o].name, g.device->parts[part].name) : wc.objects[o].name;
}

std::vector<int> ClearanceTracker::within(int object, const Eigen::Isometry3d& X_world_object, const std::vector<int>& skip,
                                          double gap) {
  nearby_.move(object, X_world_object);
  std::vector<int> out;
  for (const Proximity& p : nearby_.proximity(object, skip, gap)) out.push_back(p.other);
  return out;
}

bool ClearanceTracker::Pair::is_excused(double t) const {
  return std::any_of(excused.begin(), excused.end(), [t](const auto& w) { return t >= w.first && t <= w.second; });
}

bool ClearanceTracker::Pair::excused_over(double from, double to) const {
  return std::any_of(excused.begin(), excused.end(), [&](const auto& w) { return from >= w.first && to <= w.second; });
}

bool ClearanceTracker::provisional_at(double t) const {
  for (int o : {keeping_.first, keeping_.second}) {
    auto it = provisional_.find(o);
    if (it != provisional_.end() &&
        std::any_of(it->second.begin(), it->second.end(), [&](const auto& w) { return t >= w.first && t <= w.second; }))
      return true;
  }
  return false;
}

void ClearanceTracker::keep(Pair& pair, double distance, double t, int a, int part_a, int b, int part_b) {
  if (distance >= pair.closest()) return;
  if (distance >= -kContact && pair.is_excused(t)) return;
  Seen seen{distance, t, run_part_name(wc_, geometry_, a, part_a), run_part_name(wc_, geometry_, b, part_b)};
  // A record that may yet be excused (a load's set-down, until it lands) does not decide where
  // halving pays: a stretch left coarse beside it would be the run's closest once it is excused.
  if (seen.distance < -kContact || !provisional_at(seen.t)) best_ = std::min(best_, seen.distance);
  pair.records.push_back(std::move(seen));
}

void ClearanceTracker::saw(const Pair& pair, double distance, double t) {
  if (distance >= nearest_ || pair.is_excused(t)) return;
  if (provisional_at(t)) pending_seen_.push_back({key(keeping_.first, keeping_.second), distance, t});
  else nearest_ = distance;
}

double ClearanceTracker::Path::total() const {
  return travelled.empty() ? 0.0 : *std::max_element(travelled.back().begin(), travelled.back().end());
}

double ClearanceTracker::Path::between(size_t i, size_t j) const {
  double most = 0;
  for (size_t k = 0; k < travelled[j].size(); ++k) most = std::max(most, travelled[j][k] - travelled[i][k]);
  return most;
}

const ClearanceTracker::Path* ClearanceTracker::path(int object) const {
  auto it = paths_.find(object);
  return it == paths_.end() ? nullptr : it->second.get();
}

void ClearanceTracker::place(int object, const std::vector<Eigen::Isometry3d>& X_world) {
  if (geometry_.objects[object].device)
    nearby_.move_parts(object, X_world);
  else
    nearby_.move(object, X_world.front());
}

void ClearanceTracker::follow(double t, int object, const std::vector<Eigen::Isometry3d>& X_world, bool keep_path) {
  followed_ = true;
  std::shared_ptr<Path>& held = paths_[object];
  if (!held) held = std::make_shared<Path>();
  Path& p = *held;
  const bool device = geometry_.objects[object].device != nullptr;
  if (p.poses.empty()) {
    if (t <= interval_start_ + 1e-9 || device) {  // its first sight: the interval starts here
      p.now = X_world;
      p.t.assign(1, t);
      p.poses.assign(1, X_world);
      p.travelled.assign(1, std::vector<double>(X_world.size(), 0.0));
      p.decided = false;
      return;
    }
    // First seen mid-interval (a load still until a grasp woke it, and what rides on it): it
    // stood where the vault has it until now, at every step the others kept, so that it is
    // placed with what carries it when the tracker halves (a drum on a pallet a forklift lifted
    // at 3.02 s was measured standing where the lift left it, less the whole lift: a 44 mm gap
    // read -0.175 m at 1 Hz).
    const Eigen::Isometry3d& X_static = geometry_.objects[object].X_world_object;
    // The steps kept so far (a device's path: devices are followed first), before this one.
    const Path* ref = nullptr;
    for (const auto& [o, other] : paths_)
      if (other && other->keep && other->decided && !other->t.empty() && std::abs(other->t.front() - interval_start_) < 1e-9 &&
          (!ref || other->t.size() > ref->t.size()))
        ref = other.get();
    size_t before = 0;
    if (ref) before = std::lower_bound(ref->t.begin(), ref->t.end(), t - 1e-9) - ref->t.begin();
    p.now.assign(X_world.size(), X_static);
    if (keep_path && before > 0) {
      p.t.assign(ref->t.begin(), ref->t.begin() + before);
      p.poses.assign(before, p.now);
      p.travelled.assign(before, std::vector<double>(X_world.size(), 0.0));
      p.decided = p.keep = true;
    } else {
      p.t.assign(1, interval_start_);
      p.poses.assign(1, p.now);
      p.travelled.assign(1, std::vector<double>(X_world.size(), 0.0));
      p.decided = false;
    }
  }
  if (!p.decided) {  // the first step after the sample decides whether this interval keeps poses
    p.decided = true;
    p.keep = keep_path;
  } else if (keep_path && !p.keep && !device &&
             std::all_of(p.travelled.back().begin(), p.travelled.back().end(), [](double d) { return d == 0; })) {
    // Still since the sample and moving now (a free drum a carried one pushes): it stood where
    // it is at every step kept so far, and keeps its poses from here (unkept, the whole push was
    // subtracted from every distance measured with it: -0.26 m at 10 Hz for 1 mm of contact).
    const Path* ref = nullptr;
    for (const auto& [o, other] : paths_)
      if (other && other.get() != &p && other->keep && other->decided && !other->t.empty() &&
          std::abs(other->t.front() - interval_start_) < 1e-9 && (!ref || other->t.size() > ref->t.size()))
        ref = other.get();
    if (ref) {
      const size_t before = std::lower_bound(ref->t.begin(), ref->t.end(), t - 1e-9) - ref->t.begin();
      p.t.assign(ref->t.begin(), ref->t.begin() + before);
      p.poses.assign(before, p.now);
      p.travelled.assign(before, std::vector<double>(X_world.size(), 0.0));
      p.keep = !p.t.empty();
      if (!p.keep) {  // (no step kept yet: as it was)
        p.t.assign(1, interval_start_);
        p.poses.assign(1, p.now);
        p.travelled.assign(1, std::vector<double>(X_world.size(), 0.0));
      }
    }
  }
  // In place, without allocating: every free object of a store is followed at every step.
  if (p.keep) p.travelled.push_back(p.travelled.back());
  std::vector<double>& went = p.travelled.back();
  for (size_t k = 0; k < X_world.size(); ++k)
    if (!(p.now[k].matrix() == X_world[k].matrix()))
      went[k] += nearby_.travel_bound(object, device ? static_cast<int>(k) : -1, p.now[k], X_world[k]);
  p.now = X_world;
  if (p.keep) {
    p.t.push_back(t);
    p.poses.push_back(X_world);
  }
}

void ClearanceTracker::set_back(int object, double t_back, double t, const std::vector<Eigen::Isometry3d>& X_world) {
  auto it = paths_.find(object);
  if (it == paths_.end() || !it->second || it->second->t.empty()) return;
  Path& p = *it->second;
  const bool device = geometry_.objects[object].device != nullptr;
  // The plan's poses after t_back are not where it went.
  for (Path::Span& span : p.spans) span.to = std::min(span.to, t_back);
  p.spans.erase(std::remove_if(p.spans.begin(), p.spans.end(), [](const Path::Span& s) { return s.to <= s.from + 1e-12; }), p.spans.end());
  auto bound = [&](size_t k, const Eigen::Isometry3d& from, const Eigen::Isometry3d& to) {
    return nearby_.travel_bound(object, device ? static_cast<int>(k) : -1, from, to);
  };
  if (!p.keep) {  // unkept: its going back counts too
    for (size_t k = 0; k < X_world.size() && k < p.travelled.back().size(); ++k) p.travelled.back()[k] += bound(k, p.now[k], X_world[k]);
  } else {
    // Each kept pose after t_back (but the sample's) is where it was set back to; the travel to
    // the first of them from the one before, nothing after.
    for (size_t i = 1; i < p.t.size(); ++i) {
      if (p.t[i] <= t_back + 1e-9 || p.t[i] > t + 1e-9) continue;
      for (size_t k = 0; k < X_world.size() && k < p.travelled[i].size(); ++k)
        p.travelled[i][k] = p.travelled[i - 1][k] + bound(k, p.poses[i - 1][k], X_world[k]);
      p.poses[i] = X_world;
    }
  }
  p.now = X_world;
}

void ClearanceTracker::next_interval(double t) {
  interval_start_ = t;
  measured_before_ = std::move(measured_now_);
  measured_now_.clear();
  if (held_bytes_ > kMaxDeferredBytes) settle(kMaxDeferredBytes / 2);
  for (auto& [object, held] : paths_) {
    // A piece deferred holds this interval's path: it stays as it is, the next starts anew.
    if (held.use_count() > 1) {
      auto fresh = std::make_shared<Path>();
      fresh->now = held->now;
      held = std::move(fresh);
    }
    Path& p = *held;
    p.t.assign(1, t);
    p.poses.assign(1, p.now);
    p.travelled.assign(1, std::vector<double>(p.now.size(), 0.0));
    p.keep = p.decided = false;
    p.spans.clear();
  }
}

void ClearanceTracker::provisional(int object, double from, double to) { provisional_[object].emplace_back(from, to); }

void ClearanceTracker::glide(int object, double from, double to, double step, PoseSource source, HullSource hull) {
  std::shared_ptr<Path>& held = paths_[object];
  if (!held) held = std::make_shared<Path>();
  held->spans.push_back({from, to, step, std::move(source), std::move(hull)});
}

bool ClearanceTracker::extend(int object, double from, double to) {
  auto it = paths_.find(object);
  if (it == paths_.end() || !it->second || it->second->spans.empty() || std::abs(it->second->spans.back().to - from) > 1e-9)
    return false;
  it->second->spans.back().to = to;
  return true;
}

void ClearanceTracker::measure(double t, int moving, const std::vector<int>& skip, const std::vector<char>& parts) {
  if (!followed_) certified_ = false;  // a caller that does not follow the steps measures samples only
  measured_now_[moving] = skip;
  const Path* mine = path(moving);
  const double my_travel = mine ? mine->total() : 0.0;
  auto travel_of = [this](int other) {
    const Path* p = path(other);
    return p ? p->total() : 0.0;
  };
  // Only closer approaches than seen so far are news: the search skips pairs that cannot be.
  // Between the samples a pair came no nearer than its distance now less how far both went.
  // A watched pair is news until it cannot come nearer than its gap.
  // Nor can a pair farther than the nearest distance measured where a pair counts (nearest_,
  // which the run's closest approach is no farther than): the crane passing a store's racks
  // measured each of them within 2 m at every sample, for a closest approach it never was.
  auto could_be_news = [&](int other) {
    auto it = pairs_.find(key(moving, other));
    const double closest = std::min(nearest_, it == pairs_.end() ? INFINITY : it->second.closest());
    return (it == pairs_.end() ? closest : std::max(closest, it->second.watch())) + my_travel + travel_of(other);
  };
  const std::vector<Proximity> near = nearby_.proximity(moving, skip, kClearanceReach + my_travel, could_be_news, parts);
  // Between the samples, for a pair measured at the last one too: a load grasped since (or
  // lifted off the stack it rode on) was standing on what it is lifted off until then, and
  // that contact is no clearance.
  const auto before = measured_before_.find(moving);
  for (const Proximity& p : near) {
    Pair& pair = pairs_[key(moving, p.other)];
    keeping_ = {moving, p.other};
    if (pair.dip_at != t) pair.dips.clear(), pair.dip_at = t;  // a dip belongs to its interval
    const double other_travel = travel_of(p.other);
    const bool measured_then = before != measured_before_.end() &&
                               std::find(before->second.begin(), before->second.end(), p.other) == before->second.end();
    if (mine && my_travel + other_travel > 0 && measured_then) {
      // The distance at the last sample, where both were then: measured then, or now.
      std::optional<Proximity> then;
      if (pair.sampled_at == mine->t.front()) {
        then = pair.sampled;
      } else {
        const Path* theirs = path(p.other);
        place(moving, mine->start());
        if (theirs) place(p.other, theirs->start());
        then = nearby_.pair_distance(moving, p.other, parts);
        if (theirs) place(p.other, theirs->now);
      }
      // The sample itself first: it bounds what halving can find.
      keep(pair, p.distance, t, moving, p.part, p.other, p.other_part);
      // The other, when it moved too: kept at the same steps (two devices, a device and another's
      // load), it is placed with the moving one at each halving; else it stands where it is now,
      // and each distance measured so is less how far it went (two arms swinging past each other
      // at 1 Hz were said 0.5 m into each other, and their clearance rule was not seen broken).
      const Path* theirs = path(p.other);
      Other other{p.other, nullptr, other_travel};
      if (theirs && other_travel > 0 && theirs->keep && theirs->t == mine->t) other.path = theirs;
      if (then && mine->keep && mine->poses.size() > 1) {  // halved along the kept poses
        auto motion = std::make_shared<Motion>();
        motion->moving = moving;
        motion->other = p.other;
        motion->travel = other_travel;
        motion->with = other.path != nullptr;
        motion->mine = paths_.at(moving);
        if (theirs) motion->theirs = paths_.at(p.other);
        else if (!geometry_.objects[p.other].device) motion->other_at = nearby_.placed_pose(p.other);
        motion->parts = parts;
        refine(motion, 0, mine->poses.size() - 1, *then, p);
        for (double gap : pair.watches)  // each rule's gap: the first pose nearer, left to right
          if (!pair.dips.count(gap))
            if (auto d = first_dip(gap, moving, other, parts, *mine, 0, mine->poses.size() - 1, *then, p))
              pair.dips.insert_or_assign(gap, *d);
      }
      else if (then)
        keep_bound(pair, moving, Other{p.other, nullptr, 0}, *then, mine->t.front(), p, t, my_travel + other_travel);
      place(moving, mine->now);
      if (other.path) place(p.other, theirs->now);
    }
    keep(pair, p.distance, t, moving, p.part, p.other, p.other_part);
    saw(pair, p.distance, t);
    pair.sampled_at = t;
    pair.sampled = p;
  }
}

void ClearanceTracker::keep_bound(Pair& pair, int moving, const Other& other, const Proximity& at_i, double t_i,
                                  const Proximity& at_j, double t_j, double D, double floor) {
  const double lower = std::max(floor, interval_bound(at_i.distance - other.shift(), at_j.distance - other.shift(), D));
  const bool first = at_i.distance <= at_j.distance;
  const Proximity& nearer = first ? at_i : at_j;
  keep(pair, lower, first ? t_i : t_j, moving, nearer.part, other.object, nearer.other_part);
}

void ClearanceTracker::refine(const std::shared_ptr<const Motion>& motion, size_t i, size_t j, const Proximity& at_i,
                              const Proximity& at_j) {
  const Motion& m = *motion;
  const Path& p = *m.mine;
  const Other other = m.as_other();
  Pair& pair = pairs_[key(m.moving, m.other)];
  keeping_ = {m.moving, m.other};
  // The bound keep_bound keeps, here to decide whether halving could find news.
  const double d_i = at_i.distance, d_j = at_j.distance, D = p.between(i, j) + other.between(i, j);
  const double lower = interval_bound(d_i - other.shift(), d_j - other.shift(), D);
  // A contact no step saw may hide here (the pair apart at both ends, the bound below a touch):
  // looked for whether or not the bound is news (a blade through a plate in one step was `ok`).
  const bool hidden = other.shift() == 0 && unsure(pair, lower, d_i, d_j, p.t[i], p.t[j]);
  if (lower >= pair.closest() && !hidden) return;  // no news
  // Excused all along (a drum lifted off its pallet, set on a beam): only a penetration deeper
  // than a contact would be kept, and the bound rules that out (halving it cost the arm demo a
  // third of its time).
  if (lower >= -kContact && pair.excused_over(p.t[i], p.t[j])) return;
  // Not nearer than the run's closest so far (less the tolerance): this stretch cannot be the
  // run's closest approach by more than that; its bound, coarse but certain, is kept without
  // halving (the halving is the cost).
  if (moot(lower) && !hidden) {
    keep_bound(pair, m.moving, other, at_i, p.t[i], at_j, p.t[j], D);
    return;
  }
  if (j - i <= 1 || (!hidden && std::min(d_i, d_j) - lower <= certify_tolerance(std::min(d_i, d_j)))) {
    // Two sub-steps of a glide: halved in time, the poses from its plan (and the other's, when
    // it glides too).
    const Path::Span* span = j - i == 1 ? p.span(p.t[i], p.t[j]) : nullptr;
    const Path::Span* theirs = span && other.path ? other.path->span(p.t[i], p.t[j]) : nullptr;
    if (span && (!other.path || theirs))
      return refine_span(motion, *span, theirs, p.t[i], p.t[j], p.poses[i], p.poses[j],
                         other.path ? other.path->poses[i] : std::vector<Eigen::Isometry3d>(),
                         other.path ? other.path->poses[j] : std::vector<Eigen::Isometry3d>(), at_i, at_j);
    // Two physics steps: along the integrator's straight motion between them.
    if (hidden && j - i == 1) sweep_step(m, i, at_i, D);
    keep_bound(pair, m.moving, other, at_i, p.t[i], at_j, p.t[j], D);
    return;
  }
  Piece piece;
  piece.lower = lower;
  piece.motion = motion;
  piece.i = i;
  piece.j = j;
  piece.t_a = p.t[i];
  piece.t_b = p.t[j];
  piece.at_a = at_i;
  piece.at_b = at_j;
  defer(std::move(piece));
}

void ClearanceTracker::refine_span(const std::shared_ptr<const Motion>& motion, const Path::Span& span, const Path::Span* theirs,
                                   double t_a, double t_b, const std::vector<Eigen::Isometry3d>& X_a,
                                   const std::vector<Eigen::Isometry3d>& X_b, const std::vector<Eigen::Isometry3d>& Y_a,
                                   const std::vector<Eigen::Isometry3d>& Y_b, const Proximity& at_a, const Proximity& at_b) {
  const Motion& m = *motion;
  const Other other = m.as_other();
  Pair& pair = pairs_[key(m.moving, m.other)];
  keeping_ = {m.moving, m.other};
  // How far each went between a and b: the moving object, and the other gliding with it (else
  // it stands where it is now, having gone other.travel).
  auto went = [this](int o, const std::vector<Eigen::Isometry3d>& from, const std::vector<Eigen::Isometry3d>& to) {
    const bool device = geometry_.objects[o].device != nullptr;
    double most = 0;
    for (size_t k = 0; k < from.size() && k < to.size(); ++k)
      most = std::max(most, nearby_.travel_bound(o, device ? static_cast<int>(k) : -1, from[k], to[k]));
    return most;
  };
  const double D = went(m.moving, X_a, X_b) + (theirs ? went(m.other, Y_a, Y_b) : 0.0);
  const double d_a = at_a.distance, d_b = at_b.distance;
  double lower = interval_bound(d_a - other.shift(), d_b - other.shift(), D);
  // Where that bound would be news, the way it goes instead of how far, when it only translates.
  if (lower < pair.closest() && !theirs && span.hull && std::min(d_a, d_b) - lower > certify_tolerance(std::min(d_a, d_b)))
    lower = std::max(lower, std::min({slab_over(m, span, t_a, t_b, X_a, X_b), d_a - other.shift(), d_b - other.shift()}));
  // A contact no step saw may hide here: halved to the end whether or not it is news.
  const bool hidden = other.shift() == 0 && unsure(pair, lower, d_a, d_b, t_a, t_b);
  if (lower >= pair.closest() && !hidden) return;
  if (lower >= -kContact && pair.excused_over(t_a, t_b)) return;
  if (moot(lower) && !hidden) {
    keep_bound(pair, m.moving, other, at_a, t_a, at_b, t_b, D, lower);
    return;
  }
  // The plan has a pose at any time: halved below the physics step too, to an eighth of it (a
  // drum drifting past a post's rim read 0.21 mm under the truth, stopped at the step).
  if (t_b - t_a <= span.step * kSpanSteps ||
      (!hidden && std::min(d_a, d_b) - lower <= certify_tolerance(std::min(d_a, d_b)))) {
    keep_bound(pair, m.moving, other, at_a, t_a, at_b, t_b, D, lower);
    return;
  }
  Piece piece;
  piece.lower = lower;
  piece.motion = motion;
  piece.span = &span;
  piece.their_span = theirs;
  piece.t_a = t_a;
  piece.t_b = t_b;
  piece.X_a = X_a;
  piece.X_b = X_b;
  piece.Y_a = Y_a;
  piece.Y_b = Y_b;
  piece.at_a = at_a;
  piece.at_b = at_b;
  defer(std::move(piece));
}

double ClearanceTracker::slab_over(const Motion& m, const Path::Span& span, double t_a, double t_b,
                                   const std::vector<Eigen::Isometry3d>& X_a, const std::vector<Eigen::Isometry3d>& X_b) {
  std::vector<std::vector<Eigen::Isometry3d>>& corners = corners_;
  if (!span.hull(t_a, t_b, corners)) return -INFINITY;
  double best = -INFINITY;
  std::vector<std::vector<Eigen::Vector3d>> shifts;
  for (const std::vector<Eigen::Isometry3d>* X : {&X_a, &X_b}) {
    shifts.assign(X->size(), {});
    for (const std::vector<Eigen::Isometry3d>& corner : corners)
      for (size_t p = 0; p < X->size() && p < corner.size(); ++p) shifts[p].push_back(corner[p].translation() - (*X)[p].translation());
    place(m.moving, *X);
    if (const std::optional<double> b = nearby_.slab_bound(m.moving, m.other, m.parts, shifts)) best = std::max(best, *b - m.as_other().shift());
  }
  return best;
}

bool ClearanceTracker::later(const Piece& a, const Piece& b) {
  return a.lower != b.lower ? a.lower > b.lower : a.order > b.order;
}

size_t ClearanceTracker::bytes(const Piece& piece) {
  return sizeof(Piece) + (piece.X_a.size() + piece.X_b.size() + piece.Y_a.size() + piece.Y_b.size()) * sizeof(Eigen::Isometry3d);
}

void ClearanceTracker::hold(const Path* path, int by) {
  if (!path) return;
  auto [it, fresh] = held_.try_emplace(path, 0, 0);
  if (fresh) {
    it->second.second = sizeof(Path) + path->poses.size() * path->now.size() * sizeof(Eigen::Isometry3d) +
                        path->travelled.size() * path->now.size() * sizeof(double) + path->spans.size() * sizeof(Path::Span);
    held_bytes_ += it->second.second;
  }
  it->second.first += by;
  if (it->second.first == 0) {
    held_bytes_ -= it->second.second;
    held_.erase(it);
  }
}

void ClearanceTracker::defer(Piece piece) {
  hold(piece.motion->mine.get(), 1);
  hold(piece.motion->theirs.get(), 1);
  held_bytes_ += bytes(piece);
  piece.order = deferrals_++;
  deferred_.push_back(std::move(piece));
  std::push_heap(deferred_.begin(), deferred_.end(), later);
}

void ClearanceTracker::settle(size_t keep_bytes) {
  std::set<int> placed;
  while (!deferred_.empty() && held_bytes_ > keep_bytes) {
    std::pop_heap(deferred_.begin(), deferred_.end(), later);
    const Piece piece = std::move(deferred_.back());
    deferred_.pop_back();
    hold(piece.motion->mine.get(), -1);
    hold(piece.motion->theirs.get(), -1);
    held_bytes_ -= bytes(piece);
    const Motion& m = *piece.motion;
    Pair& pair = pairs_[key(m.moving, m.other)];
    keeping_ = {m.moving, m.other};
    // What was recorded since it was deferred may have made it moot, or no longer the closest
    // (unless a contact no step saw may hide in it).
    const bool hidden = m.as_other().shift() == 0 && unsure(pair, piece.lower, piece.at_a.distance, piece.at_b.distance, piece.t_a, piece.t_b);
    if (piece.lower >= pair.closest() && !hidden) continue;
    if (piece.lower >= -kContact && pair.excused_over(piece.t_a, piece.t_b)) continue;
    if (moot(piece.lower) && !hidden) {  // refined again, it keeps its bound unhalved
      if (piece.span)
        refine_span(piece.motion, *piece.span, piece.their_span, piece.t_a, piece.t_b, piece.X_a, piece.X_b, piece.Y_a, piece.Y_b,
                    piece.at_a, piece.at_b);
      else
        refine(piece.motion, piece.i, piece.j, piece.at_a, piece.at_b);
      continue;
    }
    halve(piece, placed);
  }
  // Put back what was placed to halve: where the run has it now.
  for (int o : placed)
    if (const Path* p = path(o)) place(o, p->now);
  for (const auto& [o, X] : put_back_) nearby_.move(o, X);
  put_back_.clear();
}

void ClearanceTracker::halve(const Piece& piece, std::set<int>& placed) {
  const Motion& m = *piece.motion;
  const Other other = m.as_other();
  placed.insert(m.moving);
  // The other stands where it stood at the interval's sample (its path's `now`, frozen then),
  // unless it moves with the moving one.
  if (m.theirs) {
    placed.insert(m.other);
    if (!m.with) place(m.other, m.theirs->now);
  } else if (m.other_at) {
    put_back_.try_emplace(m.other, nearby_.placed_pose(m.other));
    nearby_.move(m.other, *m.other_at);
  }
  if (!piece.span) {
    const Path& p = *m.mine;
    const size_t mid = (piece.i + piece.j) / 2;
    place(m.moving, p.poses[mid]);
    if (other.path) place(m.other, other.path->poses[mid]);
    const std::optional<Proximity> at_m = nearby_.pair_distance(m.moving, m.other, m.parts);
    if (!at_m) return;
    if (other.shift() == 0) saw(pairs_[key(m.moving, m.other)], at_m->distance, p.t[mid]);
    refine(piece.motion, piece.i, mid, piece.at_a, *at_m);
    refine(piece.motion, mid, piece.j, *at_m, piece.at_b);
    return;
  }
  const double t_m = (piece.t_a + piece.t_b) / 2;
  std::vector<Eigen::Isometry3d> X_m, Y_m;
  piece.span->source(t_m, X_m);
  place(m.moving, X_m);
  if (piece.their_span) {
    piece.their_span->source(t_m, Y_m);
    place(m.other, Y_m);
  }
  const std::optional<Proximity> at_m = nearby_.pair_distance(m.moving, m.other, m.parts);
  if (!at_m) return;
  if (other.shift() == 0) saw(pairs_[key(m.moving, m.other)], at_m->distance, t_m);
  // Into the other at a pose of the plan between the steps: a contact (as deep as that, at
  // least), and where the two are apart at an end, the piece swept along its plan for the
  // deepest.
  const bool into = other.shift() == 0 && at_m->distance < -kSweptDepth && !pairs_[key(m.moving, m.other)].is_excused(t_m);
  if (into) swept_.push_back({m.moving, at_m->part, m.other, at_m->other_part, t_m, -at_m->distance});
  if (into && std::max(piece.at_a.distance, piece.at_b.distance) >= -kSweptDepth) {
    const Path::Span& span = *piece.span;
    const Path::Span* theirs = piece.their_span;
    const double t_a = piece.t_a, t_b = piece.t_b;
    double D = 0;
    for (size_t k = 0; k < piece.X_a.size() && k < piece.X_b.size(); ++k)
      D = std::max(D, nearby_.travel_bound(m.moving, geometry_.objects[m.moving].device ? static_cast<int>(k) : -1, piece.X_a[k], piece.X_b[k]));
    for (size_t k = 0; theirs && k < piece.Y_a.size() && k < piece.Y_b.size(); ++k)
      D += nearby_.travel_bound(m.other, geometry_.objects[m.other].device ? static_cast<int>(k) : -1, piece.Y_a[k], piece.Y_b[k]);
    sweep(m, t_a, t_b, D, piece.at_a, [&](double s, std::vector<Eigen::Isometry3d>& X, std::vector<Eigen::Isometry3d>& Y) {
      span.source(t_a + s * (t_b - t_a), X);
      if (theirs) theirs->source(t_a + s * (t_b - t_a), Y);
    });
    place(m.moving, X_m);
    if (piece.their_span) place(m.other, Y_m);
  }
  refine_span(piece.motion, *piece.span, piece.their_span, piece.t_a, t_m, piece.X_a, X_m, piece.Y_a, Y_m, piece.at_a, *at_m);
  refine_span(piece.motion, *piece.span, piece.their_span, t_m, piece.t_b, X_m, piece.X_b, Y_m, piece.Y_b, *at_m, piece.at_b);
}

void ClearanceTracker::sweep_step(const Motion& m, size_t i, const Proximity& at_i, double D) {
  const Path& p = *m.mine;
  const Path* theirs = m.with ? m.theirs.get() : nullptr;
  // Each part's frame from its pose at step i to its pose at step i + 1: straight, turning at a
  // constant rate. No point goes farther than D over the step, at most D times the fraction of it.
  auto between = [](const std::vector<Eigen::Isometry3d>& from, const std::vector<Eigen::Isometry3d>& to, double s,
                    std::vector<Eigen::Isometry3d>& X) {
    X.resize(from.size());
    for (size_t k = 0; k < from.size(); ++k) {
      const Eigen::Quaterniond q = Eigen::Quaterniond(from[k].linear()).slerp(s, Eigen::Quaterniond(to[k].linear()));
      X[k].linear() = q.toRotationMatrix();
      X[k].translation() = (1 - s) * from[k].translation() + s * to[k].translation();
      X[k].makeAffine();
    }
  };
  sweep(m, p.t[i], p.t[i + 1], D, at_i, [&](double s, std::vector<Eigen::Isometry3d>& X, std::vector<Eigen::Isometry3d>& Y) {
    between(p.poses[i], p.poses[i + 1], s, X);
    if (theirs) between(theirs->poses[i], theirs->poses[i + 1], s, Y);
  });
}

void ClearanceTracker::sweep(const Motion& m, double t_a, double t_b, double D, const Proximity& at_a, const SweepPoses& poses) {
  if (D <= 0 || t_b <= t_a) return;
  const bool both = m.with && m.theirs;
  Pair& pair = pairs_[key(m.moving, m.other)];
  std::vector<Eigen::Isometry3d> X, Y;
  double s = 0, d = at_a.distance;
  std::optional<Proximity> deepest;
  double deepest_at = 0;
  for (int n = 0; n < 4096; ++n) {
    // Apart, as far as the fastest point cannot close (conservative advancement); inside,
    // finely, for the deepest.
    s += (d < 0 ? kSweepResolution : std::max(d, kSweepResolution)) / D;
    if (s >= 1) break;
    poses(s, X, Y);
    place(m.moving, X);
    if (both) place(m.other, Y);
    const std::optional<Proximity> at = nearby_.pair_distance(m.moving, m.other, m.parts);
    if (!at) break;
    d = at->distance;
    const double t = t_a + s * (t_b - t_a);
    if (d < -kSweptDepth && !pair.is_excused(t) && (!deepest || d < deepest->distance)) {
      deepest = at;
      deepest_at = t;
    }
    if (deepest && d >= -kSweptDepth) break;  // through: the deepest of this pass is found
  }
  place(m.moving, m.mine->now);
  if (both) place(m.other, m.theirs->now);
  if (!deepest) return;
  swept_.push_back({m.moving, deepest->part, m.other, deepest->other_part, deepest_at, -deepest->distance});
  keeping_ = {m.moving, m.other};
  keep(pair, deepest->distance, deepest_at, m.moving, deepest->part, m.other, deepest->other_part);
}

void ClearanceTracker::finish() {
  // Every set-down has landed: what was provisional is excused or counts like the rest.
  provisional_.clear();
  for (const auto& [k, pair] : pairs_) best_ = std::min(best_, pair.closest());
  for (const Measured& s : pending_seen_)
    if (!pairs_[s.key].is_excused(s.t)) nearest_ = std::min(nearest_, s.distance);
  pending_seen_.clear();
  settle(0);
}

std::optional<ClearanceTracker::Dip> ClearanceTracker::first_dip(double gap, int moving, const Other& other,
                                                                  const std::vector<char>& parts, const Path& p, size_t i, size_t j,
                                                                  const Proximity& at_i, const Proximity& at_j) {
  const double d_i = at_i.distance, d_j = at_j.distance, D = p.between(i, j) + other.between(i, j);
  if (interval_bound(d_i - other.shift(), d_j - other.shift(), D) >= gap) return std::nullopt;  // certainly clear of the gap
  if (j - i <= 1) {
    if (d_j >= gap) return std::nullopt;
    return Dip{p.t[j], d_j, run_part_name(wc_, geometry_, moving, at_j.part), run_part_name(wc_, geometry_, other.object, at_j.other_part)};
  }
  const size_t m = (i + j) / 2;
  place(moving, p.poses[m]);
  if (other.path) place(other.object, other.path->poses[m]);
  const std::optional<Proximity> at_m = nearby_.pair_distance(moving, other.object, parts);
  if (!at_m) return std::nullopt;
  if (auto early = first_dip(gap, moving, other, parts, p, i, m, at_i, *at_m)) return early;
  return first_dip(gap, moving, other, parts, p, m, j, *at_m, at_j);
}

void ClearanceTracker::watch(int a, int b, double gap) {
  Pair& pair = pairs_[key(a, b)];
  if (std::find(pair.watches.begin(), pair.watches.end(), gap) == pair.watches.end()) pair.watches.push_back(gap);
}

std::optional<ClearanceTracker::Dip> ClearanceTracker::dip(int a, int b, double gap, double t) const {
  auto it = pairs_.find(key(a, b));
  if (it == pairs_.end() || it->second.dip_at != t) return std::nullopt;
  auto d = it->second.dips.find(gap);
  if (d == it->second.dips.end()) return std::nullopt;
  return d->second;
}

void ClearanceTracker::measure_penetration(double t, int a, int b) {
  // Only shapes whose boxes overlap can be deeper than a contact into each other.
  const std::optional<Proximity> p = nearby_.pair_distance(a, b, {}, -kContact);
  if (!p || p->distance >= -kContact) return;
  keeping_ = {a, b};
  keep(pairs_[key(a, b)], p->distance, t, a, p->part, b, p->other_part);
}

void ClearanceTracker::excuse(int a, int b, double from, double to) {
  Pair& pair = pairs_[key(a, b)];
  pair.excused.emplace_back(from, to);
  std::erase_if(pair.records, [&](const Seen& s) { return s.distance >= -kContact && s.t >= from && s.t <= to; });
}

std::optional<RunSummaryFile::Clearance> ClearanceTracker::closest() const {
  const Seen* best = nullptr;
  Key best_key;
  for (const auto& [k, pair] : pairs_)
    if (!pair.records.empty() &&
        (!best || pair.records.back().distance < best->distance || (pair.records.back().distance == best->distance && k < best_key)))
      best = &pair.records.back(), best_key = k;
  if (!best) return std::nullopt;
  return RunSummaryFile::Clearance{r9(best->distance), best->a, best->b, r9(best->t), certified_ && followed_};
}

}  // namespace sscs
