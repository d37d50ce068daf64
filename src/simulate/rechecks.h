#pragma once
/// The constraints a run re-checks as the motion goes: bounds, expressions, clearances and
/// containment that read a device or an object the plan moves (overlaps are the physics'
/// collisions; reach is a property of the design, not of one motion). A constraint that starts
/// failing is a `constraint` event.
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <set>
#include <utility>
#include <vector>

#include "check/check.h"
#include "compile/workcell.h"
#include "geometry/geometry.h"
#include "simulate/clearance.h"
#include "simulate/events.h"

namespace sscs {

class ConstraintRechecks {
 public:
  /// The constraints of `wc` that read one of `moving` (the objects the plan moves), checked to
  /// `tolerance` (the scenario's sim.check_tolerance).
  ConstraintRechecks(const Workcell& wc, const std::set<int>& moving, double tolerance);
  bool any() const { return !options_.only.empty(); }
  /// The clearance rules' pairs (a `clearance` between objects, one of them moved) for the
  /// tracker to watch between samples, each at its gap less the tolerance.
  void watch(ClearanceTracker& tracker) const;
  /// The widest gap of those rules (m; 0: none): fast mode glides only farther from everything.
  double widest_watch() const {
    double most = 0;
    for (const Watched& w : watched_) most = std::max(most, w.gap);
    return most;
  }
  /// Checks them against the motion's geometry and slot values at time `t`; each that starts
  /// failing (it passed, or this is its first check) is an event in `events`. A clearance rule
  /// the tracker saw broken between the last sample and this one (a dip) starts failing at the
  /// dip's time, with its distance and margin, though the samples pass.
  void check(double t, const GeometryModel& live, const std::vector<double>& values, EventLog& events,
             const ClearanceTracker* tracker = nullptr);
  /// Whether every `inside` rule is certain to hold while its objects go at most `ahead` (m: per
  /// object, per part) further than the tracker has them gone now (fast mode's glide). When not,
  /// `room` (if given) is the share of `ahead` the tightest of them leaves room for.
  bool inside_clear(const ClearanceTracker& tracker, const std::map<int, std::vector<double>>& ahead, double* room = nullptr) const;
  /// Whether some `bound` or `expr` re-checked reads the motion itself (a moved object's
  /// location, orientation or bounding box, a device's joint values): those are also checked
  /// at every physics step between the samples (`check_step`).
  bool every_step() const { return !step_options_.only.empty(); }
  /// Checks those at time `t` (a physics step between samples): one that starts failing is an
  /// event there, `between_samples: true`.
  void check_step(double t, const GeometryModel& live, const std::vector<double>& values, EventLog& events);
  /// Whether some `inside` rule is re-checked: between the samples, each is judged by a bound,
  /// its margin at its last exact check less how far any of its objects may have gone since
  /// (the clearance tracker's travel); where that no longer clears the tolerance, exactly at
  /// that step (`check_inside_step`).
  bool watches_inside() const { return !inside_.empty(); }
  /// Between samples at time `t` (after the step the tracker followed): the `inside` rules whose
  /// bound no longer clears, checked exactly; `pose` places the run's state now in `live` and
  /// `values` first (once, when some rule must be checked).
  void check_inside_step(double t, const ClearanceTracker& tracker, const std::function<void()>& pose, const GeometryModel& live,
                         const std::vector<double>& values, EventLog& events);
  /// A campaign's load not arrived yet: what a rule says of it is not judged (it stands at its
  /// spot in the geometry, with those to come after it).
  void set_absent(int object, bool absent) {
    if (absent) absent_.insert(object);
    else absent_.erase(object);
    whole_due_ = true;
  }
  /// How many error-severity constraints started failing (the run's verdict counts them).
  size_t failures() const { return failures_; }
  /// When the run has ended and the tracker has halved what was left: each clearance rule's
  /// pair's closest approach is the worst of the episode it fell in (a 1 Hz run knows it only
  /// then).
  void finish(const ClearanceTracker& tracker, EventLog& events);

 private:
  const Workcell& wc_;
  CheckOptions options_;
  CheckOptions step_options_;  ///< the bounds and expressions that read the motion
  /// At a sample: the rules the motion can change (the spatial ones, and the bounds and
  /// expressions that read it). The others (a store's floor load, summed over its 143 drums,
  /// one of them carried) say at every sample what they said at the first: checked then, and
  /// again when a load arrives or leaves (what is absent is not judged).
  CheckOptions motion_options_;
  bool whole_due_ = true;
  /// Records each result's state; one that starts failing is an event at t.
  void judge(double t, const CheckReport& report, const std::set<int>& already, bool between_samples, EventLog& events);
  /// A rule that starts failing at t: its `constraint` event, counted when an error.
  void starts_failing(double t, int constraint, const std::vector<int>& subjects, std::optional<double> margin, Dim dim,
                      const std::string& message, bool between_samples, EventLog& events);
  /// A failing rule's episode: its event, which says the worst margin the episode reached and
  /// when (its first margin is only where it started: a gantry's drum 5 mm inside a 2 cm rule
  /// said -0.1 mm; review 22).
  using EpisodeKey = std::pair<int, std::vector<int>>;  ///< (constraint, subjects sorted)
  struct Episode {
    EpisodeKey key;
    size_t event = 0;
    double start = 0, end = INFINITY, worst = INFINITY;
  };
  std::vector<Episode> episodes_;
  std::map<EpisodeKey, size_t> open_;  ///< the episode under way, per key
  static EpisodeKey episode_key(int constraint, std::vector<int> subjects) {
    std::sort(subjects.begin(), subjects.end());
    return {constraint, subjects};
  }
  /// (constraint, subjects) reached `margin` at t: the worst of the episode under way then, if worse.
  void worsen(int constraint, const std::vector<int>& subjects, double margin, double t, EventLog& events);

  std::map<std::pair<int, std::vector<int>>, bool> failing_;  ///< (constraint, subjects) -> failing now
  std::set<int> absent_;
  size_t failures_ = 0;
  double tolerance_ = 0;
  struct Watched {
    int constraint = -1, a = -1, b = -1;
    double gap = 0;  ///< its min, m
  };
  std::vector<Watched> watched_;
  /// An `inside` rule watched between samples: per object and part (a device's parts, else one),
  /// the least of its distance to a counted face less `min` and to a face not counted (through
  /// which it must not stick out either), measured exactly at the sample or at a step since, and
  /// how far the part had gone by then: each can shrink by no more than the part and the
  /// container went (the crane's columns standing on the hall's floor, not counted, do not make
  /// its moving trolley's bound nil).
  struct Inside {
    int constraint = -1, container = -1;
    uint8_t faces = SpatialCheck::All;
    double min = 0, eps = 0;
    struct Member {
      int object = -1;
      std::vector<double> margin;          ///< per part; empty: not measured (the rule failed at the sample)
      std::vector<double> travelled_then;  ///< per part; empty: none (the sample)
    };
    std::vector<Member> members;
  };
  std::vector<Inside> inside_;
  /// Records the `inside` rules' margins at a sample (its report, and the parts measured in `live`).
  void note_inside(const CheckReport& report, const GeometryModel& live);
  /// A member's margins per part, measured in `live`.
  static std::vector<double> part_margins(const GeometryModel& live, const Inside& in, int object);
};

}  // namespace sscs
