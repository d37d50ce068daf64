#include "simulate/simulate.h"
#include "simulate/summary_file.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <algorithm>
#include <chrono>
#include <deque>
#include <limits>
#include <map>
#include <numbers>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/archive.h"
#include "core/files.h"
#include "core/pose.h"
#include "check/check.h"
#include "core/units.h"
#include "geometry/collision.h"
#include "model/device.h"
#include "simulate/campaign_outcome.h"
#include "simulate/clearance.h"
#include "simulate/rechecks.h"
#include "simulate/recorder.h"
#include "simulate/world.h"

namespace fs = std::filesystem;

namespace sscs {

const char* run_status_name(RunStatus s) {
  switch (s) {
    case RunStatus::Ok: return "ok";
    case RunStatus::Violations: return "violations";
    case RunStatus::Failed: return "failed";
  }
  return "?";
}

namespace {

constexpr double kTrackingTolerance = 0.005;  // m: the tool may lag its plan by this much
constexpr double kTurnTolerance = 1.0 * kPi / 180;  // rad: and its orientation by this much (a wrist 90 deg short "arrived")
constexpr double kLimitTolerance = 1e-3;      // rad or m past a joint limit before it is an event
constexpr double kSettleLimit = 5.0;          // s after the last step for released objects to settle
constexpr double kApart = 0.1;                // s apart before a touching pair counts as a new contact
constexpr double kRad = 180 / std::numbers::pi;
constexpr double kSupportGap = 0.005;         // m: a load this close to something when grasped stood on it
constexpr double kSetDownDrop = 0.05;         // m: released higher above what it lands on, it fell
constexpr double kRestTurnLimit = 0.02;       // rad: an object at rest turned by more moves again
constexpr double kGlideMargin = 0.001;        // m: fast mode glides only where nothing comes nearer than this
constexpr double kRoomAhead = 0.2;            // m: a glide looks this much farther, for the glides after it
constexpr double kProppedShare = 0.01;        // of its weight: a device pushing harder at the end holds it up

/// Where a run's outputs are assembled: the given work folder, else the default one.
std::string work_dir(const RunOptions& options) {
  return options.work_dir.empty() ? run_work_dir(options) : options.work_dir;
}

/// Rounded for logs: 9 decimals (nanometres, nanoradians) keep files stable and readable.

/// Where device `m`'s parts (in its frame) can be at any time of [a, b] on `track`, when only
/// slides move then: its part poses at the corners of the box its joint values stay in (an
/// affine image of the box, as slides translate; its hull is where each part can be). False
/// when a turning joint moves, or more than 4 joints do.
bool slide_corners(const Device& m, const Track& track, double a, double b, std::vector<std::vector<Eigen::Isometry3d>>& corners) {
  Eigen::VectorXd lo, hi;
  track.range(a, b, lo, hi);
  std::vector<int> moving;
  for (int j = 0; j < m.dof(); ++j) {
    if (hi[j] == lo[j]) continue;
    if (m.joint(j).type != JointType::Prismatic) return false;
    moving.push_back(j);
  }
  if (moving.size() > 4) return false;
  corners.clear();
  for (unsigned mask = 0; mask < (1u << moving.size()); ++mask) {
    Eigen::VectorXd q = lo;
    for (size_t k = 0; k < moving.size(); ++k)
      if (mask & (1u << k)) q[moving[k]] = hi[moving[k]];
    corners.push_back(m.part_poses(q));
  }
  return true;
}

/// A collision from its first contact to its last, as the run keeps it.
struct CollisionEpisode {
  int a = -1, b = -1;  ///< the objects
  size_t event = 0;    ///< its collision event
  double depth = 0;    ///< unrounded deepest
  bool measured = false;  ///< the solids' penetration was measured (else: the physics' contacts)
  RunSummaryFile::CollisionEpisode file;
};

class Run {
 public:
  Run(const Workcell& wc, const GeometryModel& geometry, const Plan& plan, const RunOptions& options)
      : wc_(wc), geometry_(geometry), plan_(plan), options_(options),
        world_(wc, geometry, physics_options(plan.settings.timestep, plan.settings.gravity, plan.settings.mode == SimMode::Fast)), clearances_(wc, geometry),
        recorder_(wc, geometry, world_, tracked(plan)), live_(geometry), live_values_(wc.values),
        rechecks_(wc, movers(plan), plan.settings.check_tolerance) {
    rechecks_.watch(clearances_);
    // The moves that set loads down: their approaches to what they land on are excused once they
    // land; until then they do not decide where the tracker halves (the store's crane run said
    // 0.1005 m at 1 Hz and 0.1368 m at 20 Hz: its drum's approach to the beams it was lowered
    // onto, excused later, had left a stretch past a neighbour coarse).
    std::map<int, int> holding;  // device -> what it holds, along the plan
    std::map<int, double> moving_since;  // device -> when its latest move began
    for (const PlannedStep& ps : plan.steps) {
      if (ps.kind == StepKind::Grasp) holding[ps.device] = ps.object;
      if (is_move(ps.kind)) moving_since[ps.device] = ps.start;
      if (ps.kind == StepKind::Release && holding.count(ps.device) && moving_since.count(ps.device)) {
        clearances_.provisional(holding[ps.device], moving_since[ps.device], ps.start + plan.settings.timestep);
        holding.erase(ps.device);
      }
    }
  }

  /// The run: each tick, the steps due start and end (grasps and releases with them), the state
  /// is recorded and watched, a frame drawn, the stops looked for, the devices driven along their
  /// tracks and the physics stepped.
  /// A failure the run found that its plan did not know: the run stopped there, to be planned
  /// again (on_failure: continue); nothing of it is to be written.
  const std::optional<FoundInRun>& replan() const { return replan_; }

  RunSummary run() {
    const double dt = plan_.settings.timestep;
    for (const Track& t : plan_.tracks) {
      world_.add_device(t.object, t.q_start);
      devices_.push_back({t.object, &t, t.q_start, tool_now(t.object), 0, Eigen::VectorXd::Zero(t.q_start.size()), false,
                          geometry_.objects[t.object].device->moved_parts(), 0, 0});
    }
    const long every = std::max(1L, std::lround(1.0 / (plan_.settings.rate * dt)));
    started_.assign(plan_.steps.size(), 0);
    ended_.assign(plan_.steps.size(), 0);
    skipped_.assign(plan_.steps.size(), 0);
    end_ = plan_.runs_to_limit ? INFINITY : plan_.end;  // (a campaign with more due past its limit: only the limit ends it)
    steps_in_order_ = std::is_sorted(plan_.steps.begin(), plan_.steps.end(),
                                     [](const PlannedStep& a, const PlannedStep& b) { return a.start < b.start; });
    // A campaign's loads are away until they arrive (never, when their spot stays taken).
    for (const auto& [o, at] : plan_.arrivals) {
      world_.set_present(o, false);
      clearances_.move(o, absent_pose(o));
      rechecks_.set_absent(o, true);
      absent_.insert(o);
      if (std::isfinite(at)) arrivals_.emplace_back(at, o);
    }
    std::sort(arrivals_.begin(), arrivals_.end());
    wall_start_ = std::chrono::steady_clock::now();
    follow_motion(0);
    long k = 0;
    double observed_at = -1;
    for (;; ++k) {
      const double t = k * dt;
      if (!begin_and_end_steps(t)) break;  // a grasp missed
      if (k % every == 0) {
        recorder_.record(t);
        observe(t);
        observed_at = t;
      } else {
        recheck_between_samples(t);
      }
      if (options_.on_frame && t >= frames_ * options_.frame_interval - dt / 2) options_.on_frame(frames_++, t, scene_pose());
      if (plan_failed(t) || settled(t) || out_of_time(t, k)) break;
      if (options_.interrupted && *options_.interrupted) {
        interrupted_ = true;
        break;
      }
      show_progress(t, k);
      if (const long n = glide(k, every); n > 0) {  // fast mode: nothing can touch until k + n
        k += n - 1;
        continue;
      }
      drive(t);
      if (plan_.settings.mode == SimMode::Fast) plan_spans(t, (k + 1) * dt);  // (before the step: what it holds now)
      world_.step();
      ++changes_;
      ++steps_;
      follow_motion(world_.time());
      after_step(world_.time());
    }
    if (options_.progress == RunOptions::Progress::Live && options_.progress_to) *options_.progress_to << "\r\x1b[K" << std::flush;
    // A row at the run's last instant, off the log rate or not: the logs, the glTF animation and
    // the page's player end where the run does (they stopped at 2.78 s of a 2.796 s run).
    if (observed_at < k * dt - dt / 2 && !interrupted_ && !replan_) {
      recorder_.record(k * dt);
      observe(k * dt);
    }
    return finish(k * dt);
  }

  /// Starts and ends the steps due at t, grasping and releasing. False when a grasp missed
  /// (the run stops).
  bool begin_and_end_steps(double t) {
    const double dt = plan_.settings.timestep;
    // Steps are in order of start: those before `first_open_` have ended, none after the first
    // not yet due has begun (a campaign's hours of steps, looked at each tick).
    // A campaign's loads due now arrive (before the steps that may take them).
    for (; next_arrival_ < arrivals_.size() && arrivals_[next_arrival_].first <= t + dt / 2; ++next_arrival_) {
      const int o = arrivals_[next_arrival_].second;
      ++changes_;
      world_.set_present(o, true);
      clearances_.move(o, geometry_.objects[o].X_world_object);
      rechecks_.set_absent(o, false);
      absent_.erase(o);
      events_.add(t, EventKind::Arrived, {{"object", wc_.objects[o].name}});
    }
    while (first_open_ < plan_.steps.size() && closed(first_open_)) ++first_open_;
    for (size_t i = first_open_; i < plan_.steps.size(); ++i) {
      const PlannedStep& ps = plan_.steps[i];
      if (!started_[i] && ps.start > t + dt / 2 && steps_in_order_) break;
      if (skipped_[i]) continue;
      if (!started_[i] && ps.start <= t + dt / 2) {
        started_[i] = 1;
        ++changes_;
        current_step_ = i;
        current_action_ = ps.device >= 0 ? fmt::format("{} {}", step_kind_name(ps.kind), wc_.objects[ps.device].name) : step_kind_name(ps.kind);
        if (options_.progress == RunOptions::Progress::Lines && options_.progress_to)
          *options_.progress_to << fmt::format("simulate: t = {:.2f} s: step {}/{} {}\n", t, i + 1, plan_.steps.size(), current_action_);
        step_event(t, EventKind::StepStart, ps);
        if (ps.kind == StepKind::Grasp && !grasp(t, ps)) return false;
        if (ps.kind == StepKind::Release && world_.held(ps.device) >= 0) release(t, ps);
        if (skipped_[i]) continue;  // its job failed here (a grasp missed), the run goes on
      }
      // The step the plan failed at began and never ended (its step_end was logged at the failure).
      if (started_[i] && !ended_[i] && ps.end <= t + dt / 2 && !plan_.failed_at(ps)) {
        ended_[i] = 1;
        ++changes_;
        // A move whose end finds its tool still off its target never arrived (driven into a
        // plate, stopped 1.55 m short): the step ends at its planned time, but the cycle was
        // not done, and its planned time is no cycle time.
        nlohmann::ordered_json extra;
        std::string short_of;
        if (is_move(ps.kind) && ps.device >= 0)
          if (const Lag lag = lag_now(ps.device, t); lag.over() > 1) {
            // Short by a distance, or turned off the target's orientation (a wrist stopped 90 deg
            // short with the tool point on its axis), or both.
            short_by_.emplace(i, lag.distance);
            if (lag.turn > kTurnTolerance) turned_by_.emplace(i, lag.turn * 180 / kPi);
            const bool short_of_it = lag.distance > kTrackingTolerance, turned = lag.turn > kTurnTolerance;
            const std::string off =
                fmt::format("{}{}{}", short_of_it ? fmt::format("{:g} m short of its target", stable(lag.distance)) : "",
                            short_of_it && turned ? " and " : "",
                            turned ? fmt::format("turned {:g} deg off {}", stable(lag.turn * 180 / kPi), short_of_it ? "it" : "its target") : "");
            short_of = fmt::format("{}'s {} (step {}) ended {} at {:g} s", wc_.objects[ps.device].name, step_kind_name(ps.kind),
                                   ps.index + 1, off, stable(t));  // numbered from 1, as everything else numbers steps
            if (unfinished_.empty()) unfinished_ = short_of;
            extra["short_by"] = r9(lag.distance);
            if (lag.turn > kTurnTolerance) extra["turned_by"] = r9(lag.turn * 180 / kPi);
          }
        step_event(t, EventKind::StepEnd, ps, extra);
        if (options_.on_step_end) options_.on_step_end(ps, t, scene_pose());
        // In a campaign the move's step failed, and its job with it (a job whose last move never
        // arrived was "done" at its planned end, and the campaign's figures counted it).
        if (ps.job >= 0 && is_move(ps.kind)) {
          const FoundInRun* known = plan_.found_at(static_cast<size_t>(ps.job), step_in_job(ps));
          if (!short_of.empty() || known) {
            if (!fail_in_run(t, ps, short_of.empty() ? known->message : short_of, EventKind::TrackingError)) return false;
            continue;
          }
        }
      }
    }
    return true;
  }

  /// A grasp step: the tool takes its object, and what stands on the object rides with it.
  /// False (a grasp_missed event, the run stopped) when the tool is not at the object.
  bool grasp(double t, const PlannedStep& ps) {
    // A failure an earlier run found here, which this run's plan knows (the campaign was planned
    // again with it): it fails here again, found or not (the runs agree up to it).
    const FoundInRun* known = ps.job >= 0 ? plan_.found_at(static_cast<size_t>(ps.job), step_in_job(ps)) : nullptr;
    // The plan found the tool at the object where planning had it; the physics may have
    // moved it since (fallen, rolled, carried on a pallet): a grasp from afar held a drum
    // 0.4 m below the gripper and the run said ok.
    if (const double gap = grasp_gap(ps.device, ps.object); gap > kGraspReach || known) {
      const double lag = lag_now(ps.device, t).distance;
      const std::string why =
          lag > kGraspReach ? fmt::format("its tool is {:g} m from where the plan put it (something held it back)", stable(lag))
                            : fmt::format("{} is not where the plan expected it (it fell, rolled, was carried or pushed)",
                                          wc_.objects[ps.object].name);
      const std::string message = gap <= kGraspReach ? known->message
                                                     : fmt::format("{} cannot grasp {}: its tool is {:g} m from it (at most {:g} m); {}",
                                                                   wc_.objects[ps.device].name, wc_.objects[ps.object].name,
                                                                   stable(gap), kGraspReach, why);
      if (plan_.jobs_fail_alone && plan_.replan && ps.job >= 0 && !known) return fail_in_run(t, ps, message, EventKind::GraspMissed);
      nlohmann::ordered_json fields = {{"step", ps.index}, {"device", wc_.objects[ps.device].name}};
      if (ps.job >= 0) fields["job"] = job_label(ps.job);
      fields["object"] = wc_.objects[ps.object].name;
      fields["distance"] = r9(gap);
      fields["message"] = message;
      events_.add(t, EventKind::GraspMissed, fields);
      return fail_in_run(t, ps, message, EventKind::GraspMissed);
    }
    world_.grasp(ps.device, ps.object);
    // Taken again after a release: held, not watched for rest (the run waited 5 s after
    // its last step for a drum in the gripper to settle). Taken off a load: it rides no
    // more (a drum picked off a lifted pallet was a load_shifted of 1.3 m).
    released_.erase(ps.object);
    rested_.erase(ps.object);
    rider_of_.erase(ps.object);
    world_.stop_riding(ps.object);
    set_down_at_.erase(ps.object);
    events_.add(t, EventKind::Grasp, {{"device", wc_.objects[ps.device].name}, {"object", wc_.objects[ps.object].name}});
    // What the load stood on when lifted is no clearance to report.
    // What it stands on: near it, and below its bottom (a drum resting on the pallet is
    // no support of the pallet: lifting the pallet 4 mm into it was excused).
    // (Its bounds reach the load's bottom and lie under its footprint: a rack whose deck
    // the drum stands on rises far above the drum's bottom, and lifting the drum off
    // the deck was a collision.)
    lifted_from_[ps.object] = bottom_of(ps.object);
    risen_.erase(ps.object);
    for (int other : stands_on(ps.object)) {
      supports_.insert({ps.object, other});
      clearances_.excuse(ps.object, other, t, lift_end(ps.device, t));  // the lift off it
    }
    if (live_.objects[ps.object].bbox_world.min().z() <= floor_under(wc_, live_, ps.object) + kSupportGap)
      supports_.insert({ps.object, -1});  // the floor
    // What stands on the load rides with it as free bodies: drums on a pallet a forklift
    // lifts (they stood still in the air).
    // Each is welded to what it stands on while it rests there (PhysicsWorld::ride).
    std::vector<int> under;
    const std::vector<int> on_load = riders(ps.object, &under);
    for (int k : on_load) world_.make_dynamic(k);
    for (size_t i = 0; i < on_load.size(); ++i) {
      const int k = on_load[i];
      rider_of_[k] = ps.object;
      rode_on_[k] = ps.object;
      X_load_rider_[k] = world_.pose(ps.object).inverse() * world_.pose(k);
      world_.ride(k, under[i]);
    }
    // Fast mode: whether the motors hold it is the physics' to say where it weighs more than the
    // device is rated for (an arm rated 20 kg took a 172 kg drum; its motors could not lift it).
    if (plan_.settings.mode == SimMode::Fast) {
      double mass = world_.mass(ps.object);
      for (int k : on_load) mass += world_.mass(k);
      const std::optional<double> rated = rated_load(ps.device);
      if ((!rated || mass > *rated) && world_.hand_over(ps.device))
        handed_.push_back({wc_.objects[ps.device].name, r9(t),
                           rated ? fmt::format("it takes {} ({:g} kg), more than its rated {:g} kg", wc_.objects[ps.object].name, r9(mass), *rated)
                                 : fmt::format("it takes {} ({:g} kg) and has no rated load (payload or capacity)",
                                               wc_.objects[ps.object].name, r9(mass))});
    }
    return true;
  }

  /// Step `ps` failed in the run (a grasp missed, a move that never arrived; its event logged,
  /// `kind` the event's). In a campaign going on after it (on_failure: continue), found now and
  /// not planned for: the campaign is planned again knowing it, so that the device's queued jobs
  /// go to other devices, and run again from the start (the physics is deterministic: the same
  /// run up to here; nothing of this run is written): false, the run stops here. Known to the
  /// plan: the job fails alone and the run goes on (true). Otherwise the run stops (false).
  bool fail_in_run(double t, const PlannedStep& ps, const std::string& message, EventKind kind) {
    if (plan_.jobs_fail_alone && ps.job >= 0) {
      const size_t step = step_in_job(ps);
      if (plan_.replan && !plan_.found_at(static_cast<size_t>(ps.job), step)) {
        replan_ = FoundInRun{static_cast<size_t>(ps.job), step, t, message};
        return false;
      }
      fail_job(t, ps, message);
      return true;
    }
    stop(kind, message);
    return false;
  }

  /// A campaign's job failed in the run at step `ps` (on_failure: continue): the job ends there,
  /// its device stands still where it is, and the steps of its jobs not begun never are
  /// (campaign-format.md, "Failure": the device is out).
  void fail_job(double t, const PlannedStep& ps, const std::string& message) {
    const int d = ps.device;
    run_failures_.push_back({ps.job, t, message});
    out_at_.emplace(d, t);
    for (size_t i = 0; i < plan_.steps.size(); ++i) {
      const PlannedStep& s = plan_.steps[i];
      const bool its = s.device == d || (s.job >= 0 && plan_.jobs[s.job].device == d);
      if (its && (!started_[i] || &s == &ps)) skipped_[i] = 1;
    }
    // The run ends when the steps left end (a device out leaves none of its own).
    end_ = plan_.runs_to_limit ? INFINITY : t;
    for (size_t i = 0; i < plan_.steps.size(); ++i)
      if (!skipped_[i]) end_ = std::max(end_, plan_.steps[i].end);
    for (const PlanFailure& f : plan_.job_failures) end_ = std::max(end_, f.t);
    if (plan_.failure) end_ = std::max(end_, plan_.failure->t);
    for (DeviceRun& dr : devices_)
      if (dr.object == d) {
        Track held;  // where it is (held back, it pressed on against what held it)
        held.object = d;
        held.q_start = world_.joints(d);
        held_tracks_.push_back(std::move(held));
        dr.track = &held_tracks_.back();
      }
  }

  /// Whether step i is over: ended, or never to run (its job failed).
  bool closed(size_t i) const { return ended_[i] || skipped_[i]; }

  /// A device's rated load (kg): its type's `payload` or `capacity` attribute, if it has one.
  std::optional<double> rated_load(int device) const {
    const Object& obj = wc_.objects[device];
    for (const char* name : {"payload", "capacity"})
      if (const int a = wc_.types[obj.type].find_attribute(name); a >= 0) return wc_.values[obj.first_slot + kFirstAttributeSlot + a];
    return std::nullopt;
  }

  /// What object `o` stands on where it is now: near it, and below its bottom (a drum resting on
  /// the pallet is no support of the pallet: lifting the pallet 4 mm into it was excused). (Its
  /// bounds reach the load's bottom and lie under its footprint: a rack whose deck the drum
  /// stands on rises far above the drum's bottom, and lifting the drum off the deck was a
  /// collision.)
  std::vector<int> stands_on(int o) {
    const Eigen::AlignedBox3d& load_box = live_.objects[o].bbox_world;
    const double bottom = load_box.min().z();
    std::vector<int> out;
    auto under_footprint = [&](const Eigen::AlignedBox3d& box) {
      const Eigen::AlignedBox2d under = Eigen::AlignedBox2d(box.min().head<2>(), box.max().head<2>())
                                            .intersection(Eigen::AlignedBox2d(load_box.min().head<2>(), load_box.max().head<2>()));
      return !under.isEmpty() && (under.sizes().array() > 0).all();
    };
    for (int other : clearances_.within(o, world_.pose(o), chain(o), kSupportGap)) {
      const ObjectGeometry& g = live_.objects[other];
      if (g.device) {
        // A device holds it up only with a part whose top is at its bottom (an AGV's deck), not
        // by reaching round it (the fingers of the gripper letting go).
        for (const Shape& sh : g.shapes) {
          const Eigen::AlignedBox3d box = shape_bounds(sh, g.X_world_object * sh.X_object_shape);
          if (std::abs(box.max().z() - bottom) <= kSupportGap && under_footprint(box)) {
            out.push_back(other);
            break;
          }
        }
        continue;
      }
      const Eigen::AlignedBox3d& box = g.bbox_world;
      if (box.min().z() <= bottom + kSupportGap && box.max().z() >= bottom - kSupportGap && under_footprint(box)) out.push_back(other);
    }
    return out;
  }

  /// A release step: the held object (and what rode on it) is let go, watched until it rests.
  void release(double t, const PlannedStep& ps) {
    int o = world_.held(ps.device);
    world_.release(ps.device);
    released_[o] = false;
    released_when_[o] = t;
    released_by_[o] = ps.device;
    // Set down on a device's deck (a pallet an AGV carried and keeps): it has landed there, on
    // the device, and is watched for rest (it never landed: the deck is a device's part, whose
    // contacts are collisions or the tool's own).
    for (int other : stands_on(o))
      if (geometry_.objects[other].device && !released_[o]) {
        released_[o] = true;
        events_.add(t, EventKind::Landed, {{"object", wc_.objects[o].name}, {"on", wc_.objects[other].name}});
        supports_.insert({o, other});
        clearances_.excuse(o, other, set_down_from(o), t);
      }
    released_at_[o] = world_.pose(o).translation();
    set_down_at_[o] = {released_at_[o], bottom_of(o)};
    // Its riders stay where they are, on it: free bodies, watched until they rest.
    for (auto it = rider_of_.begin(); it != rider_of_.end();)
      if (it->second == o) {
        released_[it->first] = true;
        set_down_at_[it->first] = {world_.pose(it->first).translation(), bottom_of(it->first)};
        world_.stop_riding(it->first);
        it = rider_of_.erase(it);
      } else {
        ++it;
      }
    events_.add(t, EventKind::Release, {{"device", wc_.objects[ps.device].name}, {"object", wc_.objects[o].name}});
  }

  /// The plan's own failure (a target it could not reach) is due at t: its event, and the run
  /// stops. A campaign's job failures before it are events, and the run goes on.
  bool plan_failed(double t) {
    const double dt = plan_.settings.timestep;
    for (; job_failures_seen_ < plan_.job_failures.size() && plan_.job_failures[job_failures_seen_].t <= t + dt / 2; ++job_failures_seen_)
      failure_event(t, plan_.job_failures[job_failures_seen_]);
    if (plan_.failure && plan_.failure->t <= t + dt / 2) {
      failure_event(t, *plan_.failure);
      stop(plan_.failure->kind, plan_.failure->message);
      return true;
    }
    return false;
  }

  void failure_event(double t, const PlanFailure& f) {
    nlohmann::ordered_json fields = {{"step", f.step}, {"device", wc_.objects[f.device].name}};
    if (f.job >= 0) fields["job"] = job_label(f.job);
    fields["message"] = f.message;
    if (f.kind == EventKind::Unreachable) fields["position_error"] = r9(f.position_error);
    events_.add(t, f.kind, fields);
  }

  /// A campaign job as events name it: `store In_3`.
  std::string job_label(int job) const {
    const PlannedJob& j = plan_.jobs[job];
    return fmt::format("{} {}", j.name, wc_.objects[j.object].name);
  }

  /// After the last step: true once every loose object rests (or 5 s have passed: not_at_rest).
  bool settled(double t) {
    const double dt = plan_.settings.timestep;
    if (t >= end_ - dt / 2) {
      if (settle_until_ < 0) settle_until_ = t + kSettleLimit;
      bool settled = true;
      for (int o : loose()) settled = settled && world_.at_rest(o);
      if (settled) {
        check_propped(t);
        return true;
      }
      if (t >= settle_until_) {
        // Still moving 5 s after the last step (rolling off a rack, rocking, sliding): where it
        // ends is unknown, so the operation is not shown to hold.
        for (int o : loose())
          if (!world_.at_rest(o)) {
            const Eigen::Vector3d p = world_.pose(o).translation();
            events_.add(t, EventKind::NotAtRest, {{"object", wc_.objects[o].name}, {"position", {r9(p.x()), r9(p.y()), r9(p.z())}},
                                                  {"speed", r9(world_.velocity(o).norm())}});
          }
        check_propped(t);
        return true;
      }
    }
    return false;
  }

  /// sim.limit of simulated time or --wall-limit of wall-clock time reached: its event, and the run stops.
  bool out_of_time(double t, long k) {
    const double dt = plan_.settings.timestep;
    const SimSettings& s = plan_.settings;
    if (t >= s.limit - dt / 2) {
      events_.add(t, EventKind::TimeLimit, {{"limit", s.limit}});
      stop(EventKind::TimeLimit, fmt::format("the run reached sim.limit ({:g} s of simulated time)", s.limit));
      return true;
    }
    if (options_.wall_limit > 0 && k % 64 == 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count() > options_.wall_limit) {
      events_.add(t, EventKind::WallLimit, {{"limit", options_.wall_limit}});
      stop(EventKind::WallLimit, fmt::format("the run took more than --wall-limit {:g} s of wall-clock time", options_.wall_limit));
      return true;
    }
    return false;
  }

  void show_progress(double t, long k) {
    const double dt = plan_.settings.timestep;
    const SimSettings& s = plan_.settings;
    if (options_.progress == RunOptions::Progress::Live && options_.progress_to && k % std::max(1L, std::lround(0.1 / dt)) == 0)
      *options_.progress_to << fmt::format("\rsimulate: {:6.1f} s of {:.1f} s planned (limit {:g} s), step {}/{} {}\x1b[K", t,
                               plan_.end, s.limit, current_step_ + 1, plan_.steps.size(), current_action_);
  }

  /// Fast mode: when nothing needs the dynamics (PhysicsWorld::quiet), the devices glide along
  /// their plan from tick k to the next tick where something is due (a sample, a step's start or
  /// end, a frame, a limit), placed kinematically, without physics steps or contact passes,
  /// provided nothing can touch anything in the meantime: every moving device (and what it holds)
  /// is farther from everything else, and its parts that may not touch from each other, than it
  /// and the others can go (their travel over the glide, bounded as the clearance tracker bounds
  /// it, at sub-steps of at most 1 degree of any joint's turn), and every `inside` rule holds
  /// with that travel. The tracker follows each sub-step, so clearances stay certified. Returns
  /// the ticks glided (0: it steps).
  long glide(long k, long every) {
    if (plan_.settings.mode != SimMode::Fast || !world_.quiet() || rechecks_.every_step()) return 0;
    const double dt = plan_.settings.timestep;
    const double t0 = k * dt;
    // Nothing may be under way that the steps judge tick by tick.
    for (const auto& [o, landed] : released_)
      if (!landed || !rested_.count(o)) return 0;
    for (const auto& [key, when] : last_contact_) {  // a collision or keep-out episode still open
      const auto& [a, part_a, b, part_b] = key;
      if (t0 - when <= kApart && (part_a >= 0 || part_b >= 0 || is_zone(a) || is_zone(b) || moving_load(a) >= 0 || moving_load(b) >= 0))
        return 0;
    }
    // To the next tick where something is due.
    long n = every - k % every;
    auto due = [&](double t) {
      if (t > t0 + dt / 2) n = std::min(n, std::max(1L, static_cast<long>(std::ceil((t - dt / 2) / dt - 1e-9)) - k));
    };
    for (size_t i = first_open_; i < plan_.steps.size(); ++i) {
      if (skipped_[i]) continue;
      if (!started_[i]) {
        due(plan_.steps[i].start);
        if (steps_in_order_) break;  // (no later step begins sooner)
      } else if (!ended_[i]) {
        due(plan_.steps[i].end);
      }
    }
    if (plan_.failure) due(plan_.failure->t);
    if (job_failures_seen_ < plan_.job_failures.size()) due(plan_.job_failures[job_failures_seen_].t);
    if (next_arrival_ < arrivals_.size()) due(arrivals_[next_arrival_].first);
    due(plan_.settings.limit);
    due(end_);
    if (options_.on_frame) due(frames_ * options_.frame_interval);
    if (n < 2) return 0;
    // A glide to the next due tick where nothing can touch; else a shorter one, as far as the
    // room found allows (the devices' travel is not proportional to time: checked again, and
    // shortened again, up to four looks).
    // After a refusal the next look is a tick later, then 2, 4, ... up to 16 (what is in contact
    // or nearly stays so a while; the ticks stepped meanwhile are as certain as a glide).
    if (k < next_glide_look_) return 0;
    std::vector<double> at;
    long glided = 0;
    for (long len = n, tries = 0; len >= 2 && tries < 4; ++tries) {  // (the room found is for the glide looked at)
      double room = 0;
      if (glide_clear(k, len, at, &room)) {
        glided = glide_to(len, at);
        break;
      }
      len = std::min(len - 1, static_cast<long>(std::floor(len * std::min(room, 1.0) * 0.8)));
    }
    glide_backoff_ = glided > 0 ? 1 : std::min(2 * glide_backoff_, 16L);
    next_glide_look_ = glided > 0 ? 0 : k + glide_backoff_;
    return glided;
  }

  /// Whether the devices can glide from tick k to k + n without anything coming within reach of
  /// what moves (`at`: the glide's sub-steps). When not, `room` (if given) is the share of the
  /// travel the nearest thing leaves room for (0: none, or not known).
  bool glide_clear(long k, long n, std::vector<double>& at, double* room) {
    const double dt = plan_.settings.timestep;
    const double t0 = k * dt;
    auto refuse = [room](double share) {
      if (room) *room = std::max(0.0, share);
      return false;
    };
    const double t1 = (k + n) * dt;
    // Sub-steps: no joint turns more than 1 degree in one (the bound from the poses at their ends
    // is then within 1e-6 of a point's path).
    int pieces = 1;
    for (const DeviceRun& dr : devices_) {
      const Device& m = *geometry_.objects[dr.object].device;
      const Eigen::VectorXd dq = dr.track->at(t1) - dr.track->at(t0);
      for (int j = 0; j < m.dof(); ++j)
        if (m.joint(j).type == JointType::Revolute) pieces = std::max(pieces, static_cast<int>(std::ceil(std::abs(dq[j]) / (kPi / 180))));
    }
    pieces = std::min<long>(pieces * 2, n);  // halves: a joint may turn back within the glide
    at.assign(pieces + 1, 0.0);
    for (int i = 0; i <= pieces; ++i) at[i] = t0 + (t1 - t0) * i / pieces;
    // How far each device (and its load) can go: the tracker's bound over the sub-steps.
    CollisionWorld& near = clearances_.world();
    std::vector<double> went(devices_.size(), 0.0), sank(devices_.size(), 0.0), load_sank(devices_.size(), 0.0);
    auto& poses = glide_poses_;  // per device, per sub-step (kept: its storage is reused glide after glide)
    poses.resize(devices_.size());
    std::map<int, std::vector<double>> ahead;  // per object, per part: how far it goes
    double all = 0;
    for (size_t d = 0; d < devices_.size(); ++d) {
      const int o = devices_[d].object;
      const Device& m = *geometry_.objects[o].device;
      const Eigen::Isometry3d& X_wo = geometry_.objects[o].X_world_object;
      const int load = world_.held(o);
      Eigen::Isometry3d X_tool_load = Eigen::Isometry3d::Identity();
      if (load >= 0) X_tool_load = world_.part_pose(o, m.tool_part).inverse() * world_.pose(load);
      poses[d].resize(pieces + 1);
      m.part_poses(devices_[d].track->at(at[0]), poses[d][0]);
      std::vector<double>& parts_went = ahead[o];
      parts_went.assign(poses[d][0].size(), 0.0);
      std::vector<double> parts_sank(poses[d][0].size(), 0.0);  // towards the floor
      for (int i = 1; i <= pieces; ++i) {
        m.part_poses(devices_[d].track->at(at[i]), poses[d][i]);
        const std::vector<Eigen::Isometry3d>& before = poses[d][i - 1];
        const std::vector<Eigen::Isometry3d>& now = poses[d][i];
        for (size_t p = 0; p < now.size(); ++p) {
          const Eigen::Isometry3d from = compose(X_wo, before[p]), to = compose(X_wo, now[p]);
          parts_went[p] += near.travel_bound(o, static_cast<int>(p), from, to);
          parts_sank[p] += near.descent_bound(o, static_cast<int>(p), from, to);
        }
        if (load >= 0) {
          ahead[load].resize(1, 0.0);
          const Eigen::Isometry3d from = X_wo * before[m.tool_part] * X_tool_load, to = X_wo * now[m.tool_part] * X_tool_load;
          ahead[load][0] += near.travel_bound(load, -1, from, to);
          load_sank[d] += near.descent_bound(load, -1, from, to);
        }
      }
      went[d] = *std::max_element(parts_went.begin(), parts_went.end());
      sank[d] = *std::max_element(parts_sank.begin(), parts_sank.end());
      if (load >= 0) went[d] = std::max(went[d], ahead[load][0]);
      all += went[d];
    }
    glide_all_ = all;
    if (all == 0) return true;  // nothing moves: nothing new can touch
    room_.resize(devices_.size());
    // Nothing within reach of what moves, where everything is now.
    for (size_t d = 0; d < devices_.size(); ++d) {
      if (went[d] == 0) continue;
      const int o = devices_[d].object;
      const Device& m = *geometry_.objects[o].device;
      // It, and the others towards it; beyond the clearance rules' gaps too (no dip below one
      // is looked for inside a glide).
      const double keep = kGlideMargin + rechecks_.widest_watch(), gap = all + keep;
      // The room found at an earlier glide, less what every glide since may have taken of it,
      // while nothing else happened: nothing is within `gap`, no need to look (the crane
      // travelling over the racks looked at each of 3,300 samples).
      Room& r = room_[d];
      const bool roomy = r.changes == changes_ && r.clear - r.spent > gap;
      double clear_all = gap + kRoomAhead;  // (nothing nearer than the reach looked at)
      // The nearest shape within `gap` (proximity lists what its bounds bring that near).
      auto nearest = [](const std::vector<Proximity>& found) {
        double d = INFINITY;
        for (const Proximity& p : found) d = std::min(d, p.distance);
        return d;
      };
      const size_t parts = geometry_.objects[o].X_object_part.size();
      motion_.resize(parts);
      for (size_t p = 0; p < parts; ++p) motion_[p] = world_.part_pose(o, static_cast<int>(p));
      near.move_parts(o, motion_);
      const int load = world_.held(o);
      std::vector<int> skip = chain(o);
      if (load >= 0) {
        skip.push_back(load);
        near.move(load, world_.pose(load));
        std::vector<int> load_skip = chain(load);
        load_skip.push_back(o);
        // The floor is no object of the collision world: a drum lowered into it glided through.
        // Only what goes down comes nearer to it (a pallet carried level at 0.1 m glides).
        if (!roomy) {
          const double clear = nearest(near.proximity(load, load_skip, gap + kRoomAhead));
          if (clear <= gap) return refuse((clear - keep) / all);
          clear_all = std::min(clear_all, clear);
        }
        if (const double above = near.lowest(load) - world_.floor_z(); above <= load_sank[d] + keep)
          return refuse(load_sank[d] > 0 ? (above - keep) / load_sank[d] : 0);
        // The load against the device's parts but the tool's (which hold it): it moves with the
        // tool, so only the joints between the tool and them bring it nearer (a truck driving
        // with its forks still keeps its pallet where it was from its mast); measured again only
        // when those joints moved.
        std::vector<char> others(parts, 1);
        for (size_t p = 0; p < parts; ++p) others[p] = !m.tool_parts()[p];
        const double own = own_distance(o, load, others, poses[d].front());
        const Eigen::Isometry3d X_tool_load = world_.part_pose(o, m.tool_part).inverse() * world_.pose(load);
        const double own_gap = load_own_travel(o, load, others, poses[d], X_tool_load) + keep;
        if (own <= own_gap) return refuse(own_gap > keep ? (own - keep) / (own_gap - keep) : 0);
      }
      if (!roomy) {
        const double clear = nearest(near.proximity(o, skip, gap + kRoomAhead, nullptr, devices_[d].moving_parts));
        if (clear <= gap) return refuse((clear - keep) / all);
        r = {changes_, std::min(clear_all, clear), 0.0};
      }
      if (const double above = near.lowest(o, devices_[d].moving_parts) - world_.floor_z(); above <= sank[d] + keep)
        return refuse(sank[d] > 0 ? (above - keep) / sank[d] : 0);
      // Its own parts: how far one can come towards another it may not touch is its travel in
      // the other's frame (a truck's drive moves no part against another, its mast's lift does).
      if (!near.self_clear(o, 2 * went[d] + kGlideMargin) && !near.self_clear(o, own_travel(o, poses[d]) + kGlideMargin))
        return refuse(0.5);
    }
    if (rechecks_.watches_inside()) {
      double share = INFINITY;
      if (!rechecks_.inside_clear(clearances_, ahead, &share)) return refuse(share);
    }
    return true;
  }

  /// The distance from load `load`, held by device `o`, to its parts `others` (parts: where they
  /// are now, in the device's frame), measured when the parts moved against the tool since the
  /// last time.
  double own_distance(int o, int load, const std::vector<char>& others, const std::vector<Eigen::Isometry3d>& parts) {
    const Device& m = *geometry_.objects[o].device;
    OwnMemo& memo = own_memo_[o];
    bool same = memo.load == load && memo.parts.size() == parts.size();
    for (size_t p = 0; same && p < parts.size(); ++p)
      same = (parts[m.tool_part].inverse() * parts[p]).isApprox(memo.parts[m.tool_part].inverse() * memo.parts[p], 1e-12);
    if (!same) {
      const std::optional<Proximity> found = clearances_.world().pair_distance(o, load, others);
      memo = {load, parts, found ? found->distance : INFINITY};
    }
    return memo.distance;
  }

  /// How far a shape of `object` (device part `part`, or -1: an object that is none) can come
  /// towards device part `frame` over a glide's sub-steps: the sum of its travel in that part's
  /// frame, `pose(i)` its pose at sub-step i in the device's frame.
  template <class Pose>
  double travel_towards(int object, int part, int frame, const std::vector<std::vector<Eigen::Isometry3d>>& poses, Pose pose) {
    CollisionWorld& near = clearances_.world();
    double went = 0;
    for (size_t i = 1; i < poses.size(); ++i)
      went += near.travel_bound(object, part, poses[i - 1][frame].inverse() * pose(i - 1), poses[i][frame].inverse() * pose(i));
    return went;
  }

  /// How far load `load`, held at device `o`'s tool, can come towards its parts `others` over
  /// the poses of its parts at a glide's sub-steps: its travel in each one's frame.
  double load_own_travel(int o, int load, const std::vector<char>& others, const std::vector<std::vector<Eigen::Isometry3d>>& poses,
                         const Eigen::Isometry3d& X_tool_load) {
    const int tool = geometry_.objects[o].device->tool_part;
    double most = 0;
    for (size_t p = 0; p < others.size(); ++p)
      if (others[p])
        most = std::max(most, travel_towards(load, -1, static_cast<int>(p), poses, [&](size_t i) { return poses[i][tool] * X_tool_load; }));
    return most;
  }

  /// How far a part of device `o` can come towards another it may not touch over the poses of
  /// its parts at a glide's sub-steps: the most the two travel in each other's frames.
  double own_travel(int o, const std::vector<std::vector<Eigen::Isometry3d>>& poses) {
    const Device& m = *geometry_.objects[o].device;
    const int parts = static_cast<int>(poses.front().size());
    double most = 0;
    for (int a = 0; a < parts; ++a)
      for (int b = a + 1; b < parts; ++b)
        if (!m.may_touch(a, b))
          most = std::max(most, travel_towards(o, a, b, poses, [&](size_t i) { return poses[i][a]; }) +
                                    travel_towards(o, b, a, poses, [&](size_t i) { return poses[i][b]; }));
    return most;
  }

      /// The glide itself: each sub-step placed and followed, the devices' travel and limits kept.
  long glide_to(long n, const std::vector<double>& at) {
    for (Room& r : room_) r.spent += glide_all_;
    // Between its sub-steps the tracker halves in time, with poses from the plan.
    plan_spans(at.front(), at.back());
    for (size_t i = 1; i < at.size(); ++i) {
      for (const DeviceRun& dr : devices_) world_.place(dr.object, dr.track->at(at[i]));
      world_.advance(at[i] - at[i - 1]);
      follow_motion(at[i]);
      for (DeviceRun& dr : devices_) account(dr, at[i]);
    }
    ++glides_;
    return n;
  }

  /// Fast mode: from `from` to `to` each device on its plan (and the load it holds rigidly) is
  /// where its plan has it at any time: the tracker may halve that stretch in time below the
  /// physics step, with poses from the plan. A glide's, and each step a device on its plan takes
  /// (a run stepping at 1000 Hz, or past what a clearance rule watches, kept each step's bound
  /// whole: up to half a step's travel below the truth, where a glide's is within 0.1 mm).
  void plan_spans(double from, double to) {
    for (const DeviceRun& dr : devices_) {
      const int o = dr.object;
      if (!world_.on_plan(o)) continue;
      const Device& m = *geometry_.objects[o].device;
      const Eigen::Isometry3d X_wo = geometry_.objects[o].X_world_object;
      const Track* track = dr.track;
      // Its step after a step it took on its plan, holding what it held as it held it (the
      // grasp's placement, which the world places the load with): that span goes on (two
      // std::functions a device a step were a third of e2e.fast's time).
      Eigen::Isometry3d X_tool_load = Eigen::Isometry3d::Identity();
      const int held = world_.rigid_load(o, &X_tool_load);
      SpanKey& last = span_keys_[o];
      const bool same = last.load == held && (held < 0 || last.X_tool_load.matrix() == X_tool_load.matrix());
      last = {held, X_tool_load};
      if (same && clearances_.extend(o, from, to) && (held < 0 || clearances_.extend(held, from, to))) continue;
      clearances_.glide(
          o, from, to, plan_.settings.timestep,
          [&m, X_wo, track](double t, std::vector<Eigen::Isometry3d>& X) {
            X = m.part_poses(track->at(t));
            for (auto& x : X) x = X_wo * x;
          },
          [&m, X_wo, track](double a, double b, std::vector<std::vector<Eigen::Isometry3d>>& corners) {
            if (!slide_corners(m, *track, a, b, corners)) return false;
            for (auto& X : corners)
              for (auto& x : X) x = X_wo * x;
            return true;
          });
      if (const int load = held; load >= 0) {
        clearances_.glide(
            load, from, to, plan_.settings.timestep,
            [&m, X_wo, track, X_tool_load](double t, std::vector<Eigen::Isometry3d>& X) {
              X.assign(1, X_wo * m.part_poses(track->at(t))[m.tool_part] * X_tool_load);
            },
            [&m, X_wo, track, X_tool_load](double a, double b, std::vector<std::vector<Eigen::Isometry3d>>& corners) {
              if (!slide_corners(m, *track, a, b, corners)) return false;
              for (auto& X : corners) X.assign(1, X_wo * X[m.tool_part] * X_tool_load);
              return true;
            });
      }
    }
  }

  struct SpanKey {
    int load = -2;  ///< what the device held rigidly when its last span was made (-1: nothing; -2: none made)
    Eigen::Isometry3d X_tool_load = Eigen::Isometry3d::Identity();
  };
  std::map<int, SpanKey> span_keys_;  ///< plan_spans()'s, by device

  /// Each device driven towards where its track is at the next tick.
  void drive(double t) {
    const double dt = plan_.settings.timestep;
    for (const DeviceRun& dr : devices_) {
      Eigen::VectorXd q1 = dr.track->at(t + dt);
      world_.drive(dr.object, q1, (q1 - dr.track->at(t)) / dt);
    }
  }

  /// Writes every output into a hidden temporary folder beside the target, then renames it
  /// (and/or packs it into the bundle): nothing under the requested names until complete.
  /// Returns why it could not ("" when written).
  std::string write(const RunSummary& summary) {
    std::string error;
    const fs::path tmp = work_dir(options_);
    std::error_code ec;
    auto put = [&](const std::string& rel, const std::string& text) {
      if (!error.empty()) return;
      fs::path p = tmp / rel;
      fs::create_directories(p.parent_path(), ec);
      std::ofstream f(p, std::ios::binary);
      f << text;
      if (ec || !f) error = fmt::format("cannot write '{}': {}", p.string(), ec ? ec.message() : std::strerror(errno));
    };
    put("summary.json", fmt::format("{}\n", summary_json(summary).dump(2)));
    put("events.jsonl", events_.jsonl());
    if (campaign_) put("jobs.csv", campaign_->jobs_csv);
    if (campaign_ && options_.final_vault) put("final.yaml", options_.final_vault(final_state()));
    for (const auto& [rel, text] : recorder_.files()) put(rel, text);
    if (options_.inputs)
      for (const auto& [rel, bytes] : options_.inputs->resolved) put(rel, bytes);
    if (error.empty() && !options_.bundle.empty()) {
      std::string zip_tmp = temp_path_for(options_.bundle);
      error = zip_folder(tmp.string(), zip_tmp);
      if (error.empty()) error = commit_file(zip_tmp, options_.bundle);
      else std::remove(zip_tmp.c_str());
    }
    if (error.empty() && !options_.out_dir.empty()) error = commit_dir(tmp.string(), options_.out_dir);
    fs::remove_all(tmp, ec);
    return error;
  }

 private:
  struct DeviceRun {
    int object;
    const Track* track;
    Eigen::VectorXd q_prev;
    Eigen::Vector3d tool_prev;
    double path = 0;
    Eigen::VectorXd travel;
    bool lagging = false;
    std::vector<char> moving_parts;  // parts below a revolute or prismatic joint
    double largest_lag = 0;  ///< of the current lagging episode, as Lag::over()
    size_t lag_event = 0;    ///< its tracking_error event
  };

  Eigen::Vector3d tool_now(int d) const {
    const Device& m = *geometry_.objects[d].device;
    return (world_.part_pose(d, m.tool_part) * m.X_part_tool).translation();
  }

  std::string part_name(int o, int part) const { return run_part_name(wc_, geometry_, o, part); }

  /// How far a device's tool is from where its plan puts it: the distance (m) and the turn
  /// between the two orientations (rad). Over the tolerance when either is.
  struct Lag {
    double distance = 0, turn = 0;
    /// How far over its tolerance the larger of the two is (1: at it).
    double over() const { return std::max(distance / kTrackingTolerance, turn / kTurnTolerance); }
  };
  Lag lag_of(const DeviceRun& dr, double t) const {
    const ObjectGeometry& g = geometry_.objects[dr.object];
    const Device& m = *g.device;
    const Eigen::Isometry3d planned = g.X_world_object * m.tool_pose(dr.track->at(t));
    const Eigen::Isometry3d now = world_.part_pose(dr.object, m.tool_part) * m.X_part_tool;
    return {(now.translation() - planned.translation()).norm(), Eigen::AngleAxisd(now.linear() * planned.linear().transpose()).angle()};
  }
  Lag lag_now(int d, double t) const {
    for (const DeviceRun& dr : devices_)
      if (dr.object == d) return lag_of(dr, t);
    return {};
  }

  /// Which of its job's steps `ps` is (0-based, in the template's order: the plan's steps of
  /// a job have increasing indices).
  size_t step_in_job(const PlannedStep& ps) const {
    size_t k = 0;
    for (const PlannedStep& s : plan_.steps)
      if (s.job == ps.job && s.index < ps.index) ++k;
    return k;
  }

  void step_event(double t, EventKind kind, const PlannedStep& ps, const nlohmann::ordered_json& extra = {}) {
    nlohmann::ordered_json f = {{"step", ps.index}, {"action", step_kind_name(ps.kind)}};
    if (ps.device >= 0) f["device"] = wc_.objects[ps.device].name;
    if (ps.job >= 0) f["job"] = job_label(ps.job);
    for (const auto& [key, value] : extra.items()) f[key] = value;
    events_.add(t, kind, f);
  }

  /// A carried load still pressing into what it was lifted from (the floor included) by less
  /// than kSupportGap: the lift itself, not a collision.
  bool lifting_off(const PhysicsContact& c) const {
    if (c.depth >= kSupportGap) return false;
    // Only at the load's underside: a drum dragged into the upright of the rack it was lifted
    // from ran ok (the whole rack was its support). And only until it has risen kSupportGap:
    // lifted 45 mm and pushed sideways into that upright, its contact at the bottom rim was taken
    // for the lift; carried 3 m and lowered 5 cm into the floor, so was the floor's.
    for (auto [load, other] : {std::pair{c.a, c.b}, std::pair{c.b, c.a}})
      if (load >= 0 && held_anywhere(load) && supports_.count({load, other}) &&
          c.point.z() <= live_.objects[load].bbox_world.min().z() + kSupportGap) {
        if (!risen_.count(load)) return true;
      }
    return false;
  }

  /// The gripper holding its load is not a collision: the tool's part (and the parts it
  /// carries) against what it holds. Nor is it touching, by less than kTargetTouch, a load it
  /// is about to grasp or has just released, or the object its current move_to goes to (a tool
  /// set down on a drum's top, as `reach` lets the tool touch its target); deeper is.
  bool gripper_meets_its_load(const PhysicsContact& c, double t) const {
    for (auto [dev, part, other] : {std::tuple{c.a, c.part_a, c.b}, std::tuple{c.b, c.part_b, c.a}}) {
      if (dev < 0 || part < 0 || other < 0 || !geometry_.objects[dev].device) continue;
      if (!geometry_.objects[dev].device->tool_parts()[part]) continue;
      if (world_.held(dev) == other) return true;
      if (c.depth >= kTargetTouch) continue;
      // A touch that holds the tool back from its plan is a collision too: motors do not sink a
      // tool into scenery, it is stopped (a tool planned 4 mm into a drum touched it by 5 um).
      if (lag_now(dev, t).distance > kTargetTouch) continue;
      std::vector<int> loads = handled(dev, t);
      if (std::find(loads.begin(), loads.end(), other) != loads.end() && !pushed_since_release(other)) return true;
      if (move_target(dev, t) == other) return true;
    }
    return false;
  }

  /// The object the device's latest move (started by t) goes to, when it is a move_to an object.
  int move_target(int device, double t) const {
    int target = -1;
    for (const PlannedStep& ps : plan_.steps)
      if (ps.device == device && ps.start <= t && (ps.kind == StepKind::MoveTo || ps.kind == StepKind::MoveJoints)) target = ps.target;
    return target;
  }

  /// After each physics step: where every device part and free object is, for the clearance
  /// tracker's bound between samples; the poses of what moves by a device are kept.
  void follow_motion(double t) {
    for (const DeviceRun& dr : devices_) {
      const size_t n = geometry_.objects[dr.object].X_object_part.size();
      motion_.resize(n);
      for (size_t k = 0; k < n; ++k) motion_[k] = world_.part_pose(dr.object, static_cast<int>(k));
      clearances_.follow(t, dr.object, motion_, true);
    }
    // What is carried keeps its poses, to be placed with the device that carries it when the
    // tracker halves; so does what moves of itself (falling, pushed: from the step it starts to,
    // ClearanceTracker::follow); and so does every free object over an interval in which a grasp begins,
    // for until then nothing carries it (keeping is decided at the interval's first step): a
    // drum riding a pallet a forklift lifted mid-interval was measured standing where it ended,
    // less the whole lift, and a 44 mm gap read -0.175 m at 1 Hz.
    const bool grasping = grasp_in_interval(t);
    for (size_t o = 0; o < wc_.objects.size(); ++o)
      if (world_.dynamic(static_cast<int>(o))) {
        motion_.assign(1, world_.pose(static_cast<int>(o)));
        clearances_.follow(t, static_cast<int>(o), motion_,
                           grasping || moving_load(static_cast<int>(o)) >= 0 || !world_.at_rest(static_cast<int>(o)));
      }
  }

  /// Whether a grasp begins in the sample interval that holds `t` (from the sample before it to
  /// the one after): looked up once an interval, for every physics step asks.
  bool grasp_in_interval(double t) {
    const double period = 1.0 / plan_.settings.rate, dt = plan_.settings.timestep;
    const long interval = static_cast<long>(std::floor(t / period + 1e-9));
    if (interval == grasp_interval_.first) return grasp_interval_.second;
    const double from = interval * period - dt, to = from + period + 2 * dt;
    grasp_interval_ = {interval, std::any_of(plan_.steps.begin(), plan_.steps.end(), [&](const PlannedStep& ps) {
                         return ps.kind == StepKind::Grasp && ps.start >= from && ps.start <= to;
                       })};
    return grasp_interval_.second;
  }
  std::pair<long, bool> grasp_interval_{-1, false};  ///< grasp_in_interval()'s last answer

  /// The load a device holds that `o` is or rides on, else -1.
  int moving_load(int o) const {
    if (o < 0) return -1;
    if (held_anywhere(o)) return o;
    auto r = rider_of_.find(o);
    return r != rider_of_.end() && held_anywhere(r->second) ? r->second : -1;
  }

  /// How far device d's tool is from object o's solids where the physics has it now (m).
  double grasp_gap(int d, int o) { return clearances_.distance_to_point(o, world_.pose(o), tool_now(d)); }

  /// A released object's first touch of a carried load or what rides on it: a landing, and a
  /// rider of that load from then on.
  bool lands_on_carried(const PhysicsContact& c, int load_a, int load_b, double t) {
    for (auto [o, load, other] : {std::tuple{c.a, load_b, c.b}, std::tuple{c.b, load_a, c.a}}) {
      auto it = released_.find(o);
      if (load < 0 || it == released_.end() || it->second || (other >= 0 && geometry_.objects[other].device)) continue;
      it->second = true;
      events_.add(t, EventKind::Landed, {{"object", wc_.objects[o].name}, {"on", part_name(other, -1)}});
      released_.erase(it);
      set_down_at_.erase(o);  // it rides on the load from here: where it rests is the load's doing
      supports_.insert({load, o});  // what it landed on, and what landed on the load: no clearances
      supports_.insert({o, other});
      clearances_.excuse(o, other, set_down_from(o), t);
      clearances_.excuse(o, load, set_down_from(o), t);
      rider_of_[o] = load;
      rode_on_[o] = load;
      X_load_rider_[o] = world_.pose(load).inverse() * world_.pose(o);
      world_.ride(o, other);
      return true;
    }
    return false;
  }

  /// What stands on `load` now, and on those, and so on: any object (not a device or a
  /// container, not held) that touches it (within kSupportGap), with its bottom above the
  /// load's bottom and the middle of its footprint over the load's, whichever its parent (a drum
  /// whose parent was the hall stayed in the air when its pallet was lifted; a drum whose parent
  /// was the pallet, standing 3 m from it, was carried along as a rider; a drum standing beside
  /// the load on a pallet of its own was taken for one).
  std::vector<int> riders(int load, std::vector<int>* stands_on = nullptr) {
    std::vector<int> out;
    std::set<int> seen = {load};
    const std::vector<char> is_container = containers(wc_);
    for (size_t next = 0, from = load;; from = out[next++]) {
      const Eigen::AlignedBox3d& under = live_.objects[from].bbox_world;
      // The load's footprint in its own frame (a tray turned 45 deg has empty corners in its
      // world bounds: a drum beside it, on a plank of its own, was taken for a rider).
      Eigen::AlignedBox3d local;
      for (const Shape& sh : geometry_.objects[from].shapes) local.extend(shape_bounds(sh, sh.X_object_shape));
      const Eigen::Isometry3d X_load_world = world_.pose(static_cast<int>(from)).inverse();
      for (int k : clearances_.within(static_cast<int>(from), world_.pose(static_cast<int>(from)), chain(static_cast<int>(from)), kSupportGap)) {
        const Eigen::AlignedBox3d& box = live_.objects[k].bbox_world;
        const Eigen::Vector2d middle = (X_load_world * box.center()).head<2>();
        const bool over = (middle.array() >= local.min().head<2>().array()).all() && (middle.array() <= local.max().head<2>().array()).all();
        if (is_container[k] || geometry_.objects[k].device || held_anywhere(k) || box.min().z() <= under.min().z() + kSupportGap ||
            !over || !seen.insert(k).second)
          continue;
        out.push_back(k);
        if (stands_on) stands_on->push_back(static_cast<int>(from));
      }
      if (next >= out.size()) break;
    }
    return out;
  }

  /// The free bodies no device holds: released objects and what rides (or rode) on a load.
  std::set<int> loose() const {
    std::set<int> out;
    for (const auto& [o, landed] : released_) out.insert(o);
    for (const auto& [o, load] : rider_of_) out.insert(o);
    std::erase_if(out, [&](int o) { return held_anywhere(o); });
    return out;
  }

  /// Whether a and b are a load and what rode on it when it was lifted (or two of its riders).
  bool one_stack(int a, int b) const {
    auto carrier = [&](int o) {
      auto it = rode_on_.find(o);
      return it == rode_on_.end() ? o : it->second;
    };
    return a >= 0 && b >= 0 && carrier(a) == carrier(b);
  }

  /// At the trajectory rate: a rider that moved on its carried load by more than
  /// kTrackingTolerance (a drum sliding on a pallet the forks swing) is an event, once a rider,
  /// its `shift` the largest seen while carried.
  void check_riders(double t) {
    for (const auto& [o, load] : rider_of_) {
      if (!held_anywhere(load) || held_anywhere(o)) continue;
      const double shift = ((world_.pose(load).inverse() * world_.pose(o)).translation() - X_load_rider_.at(o).translation()).norm();
      auto ev = shifted_.find(o);
      if (ev == shifted_.end() && shift > kTrackingTolerance) {
        shifted_[o] = {events_.add(t, EventKind::LoadShifted, {{"object", wc_.objects[o].name}, {"on", wc_.objects[load].name}, {"shift", r9(shift)}}), shift};
      } else if (ev != shifted_.end() && shift > ev->second.second) {
        ev->second.second = shift;
        events_.update(ev->second.first, "shift", r9(shift));
      }
    }
  }

  bool is_zone(int o) const { return o >= 0 && wc_.types[wc_.objects[o].type].zone; }

  bool held_anywhere(int o) const {
    for (const DeviceRun& dr : devices_)
      if (world_.held(dr.object) == o) return true;
    return false;
  }

  void after_step(double t) {
    // Contacts: a pair is one event until it has been apart for kApart (contacts flicker).
    for (const PhysicsContact& c : world_.contacts()) {
      // A device's part or its load inside a keep-out zone (the physics reports no other contact
      // of a zone, and lets nothing push on it): an event per episode, a violation of the run.
      if (const int zone = is_zone(c.a) ? c.a : is_zone(c.b) ? c.b : -1; zone >= 0) {
        auto key = std::make_tuple(c.a, c.part_a, c.b, c.part_b);
        auto last = last_contact_.find(key);
        const bool ongoing = last != last_contact_.end() && t - last->second <= kApart;
        last_contact_[key] = t;
        if (!ongoing)
          events_.add(t, EventKind::KeepOut, {{"zone", wc_.objects[zone].name},
                                              {"by", zone == c.a ? part_name(c.b, c.part_b) : part_name(c.a, c.part_a)},
                                              {"point", {r9(c.point.x()), r9(c.point.y()), r9(c.point.z())}}, {"depth", r9(c.depth)}});
        continue;
      }
      // An excused contact (a tool touching its target by less than 1 mm, a load lifting off)
      // does not open an episode: the same pair going deeper later is a collision (it was taken
      // for the ongoing touch, and a tool 4 cm inside its target ran `ok`).
      if (gripper_meets_its_load(c, t) || lifting_off(c)) continue;
      // A load and what rides on it move together: their contacts are support, not collisions.
      const int load_a = moving_load(c.a), load_b = moving_load(c.b);
      if (load_a >= 0 && load_a == load_b) continue;
      // Set down on a carried load (a drum put on the pallet a forklift holds): it lands there
      // and rides on it from then on (it was a collision of the carried load).
      if (lands_on_carried(c, load_a, load_b, t)) continue;
      auto key = std::make_tuple(c.a, c.part_a, c.b, c.part_b);
      auto last = last_contact_.find(key);
      bool ongoing = last != last_contact_.end() && t - last->second <= kApart;
      bool device_part = (c.a >= 0 && c.part_a >= 0) || (c.b >= 0 && c.part_b >= 0);
      bool carried = load_a >= 0 || load_b >= 0;
      // Touching is no collision, as `check` has it (kTouchTolerance, 1 um): a drum carried along a plate
      // exactly at its face collided on one side and not on its mirror image (depths of 1e-8 m).
      // Not for a free body a device touches: forks dragging a pallet they set down do so by
      // friction, at no depth.
      auto free_body = [&](int o) { return o >= 0 && world_.dynamic(o) && !held_anywhere(o); };
      if ((device_part || carried) && !ongoing && c.depth <= kTouchTolerance && !free_body(c.a) && !free_body(c.b)) continue;
      last_contact_[key] = t;
      if (device_part || carried) {
        // An episode from its first contact to its last: its event grows with it (the first
        // contact's depth was all it said while a forklift drove 1.4 m through a drum). Once
        // the load is let go the pair's contact is no collision any more: it lands.
        if (ongoing) {
          if (auto ep = collision_of_.find(key); ep != collision_of_.end()) grow_collision(collisions_[ep->second], t, c.depth, &c.point);
          continue;
        }
        const bool set_back = hand_over(t, c);
        CollisionEpisode ep;
        ep.a = c.a;
        ep.b = c.b;
        ep.file = {part_name(c.a, c.part_a), part_name(c.b, c.part_b), r9(t), r9(t), r9(c.depth), r9(t),
                   std::vector<double>{r9(c.point.x()), r9(c.point.y()), r9(c.point.z())}};
        ep.event = events_.add(t, EventKind::Collision, {{"a", ep.file.a}, {"b", ep.file.b},
                               {"point", {r9(c.point.x()), r9(c.point.y()), r9(c.point.z())}}, {"depth", r9(c.depth)},
                               {"end", r9(t)}, {"deepest_at", r9(t)}});
        ep.depth = c.depth;
        // Handed over from the pose before this step: the contact's depth was a pose the run
        // then left (review 23: 4.657 mm for a blade whose run went 2.137 mm deep); the
        // physics' contacts from here say how deep it goes.
        if (set_back) {
          ep.depth = 0;
          ep.file.depth = 0;
          events_.update(ep.event, "depth", 0.0);
        }
        collision_of_[key] = collisions_.size();
        collisions_.push_back(std::move(ep));
        continue;
      }
      // A released object's touch of anything but a device is its landing, also one that began
      // before the release (a drum let go while pressed into another never landed, rested or
      // was judged displaced).
      if (one_stack(c.a, c.b)) continue;  // a released pallet touching its own drum has not landed
      for (int o : {c.a, c.b}) {
        auto it = released_.find(o);
        if (it != released_.end() && !it->second) {
          it->second = true;
          int other = o == c.a ? c.b : c.a;
          events_.add(t, EventKind::Landed, {{"object", wc_.objects[o].name}, {"on", part_name(other, -1)}});
          supports_.insert({o, other});
          if (other >= 0) clearances_.excuse(o, other, set_down_from(o), t);  // the move that set it down
        }
      }
    }
    continue_through_overlap(t);
    // One that moves again after its rest (woken when what held it went away: a drum leaning
    // on the fingers that drew back) is watched until it rests again, and judged there.
    for (auto it = rested_.begin(); it != rested_.end();) {
      const Eigen::Isometry3d X = world_.pose(it->first);
      const double turned = Eigen::AngleAxisd(X.linear() * it->second.linear().transpose()).angle();
      if ((X.translation() - it->second.translation()).norm() > kTrackingTolerance || turned > kRestTurnLimit) it = rested_.erase(it);
      else ++it;
    }
    for (auto& [o, landed] : released_)
      if (landed && world_.at_rest(o) && !rested_.count(o)) {
        rested_[o] = world_.pose(o);
        const Eigen::Vector3d p = world_.pose(o).translation();
        events_.add(t, EventKind::AtRest, {{"object", wc_.objects[o].name}, {"position", {r9(p.x()), r9(p.y()), r9(p.z())}}});
        check_displaced(t, o, p);
      }
    for (DeviceRun& dr : devices_) account(dr, t);
  }

  /// A device's joint travel and tool path since the last step, and its joints past their limits.
  void account(DeviceRun& dr, double t) {
    // Its load has risen off what it stood on: from here its contacts with that are collisions.
    if (const int load = world_.held(dr.object); load >= 0 && !risen_.count(load))
      if (auto from = lifted_from_.find(load); from != lifted_from_.end() && bottom_of(load) >= from->second + kSupportGap)
        risen_.insert(load);
    const Device& m = *geometry_.objects[dr.object].device;
    Eigen::VectorXd q = world_.joints(dr.object);
    dr.travel += (q - dr.q_prev).cwiseAbs();
    dr.q_prev = q;
    Eigen::Vector3d tool = tool_now(dr.object);
    dr.path += (tool - dr.tool_prev).norm();
    dr.tool_prev = tool;
    for (int j = 0; j < m.dof(); ++j) {
      const Joint& jt = m.joint(j);
      bool past = q[j] < jt.lower - kLimitTolerance || q[j] > jt.upper + kLimitTolerance;
      auto key = std::make_pair(dr.object, j);
      if (past && !over_limit_.count(key)) {
        over_limit_.insert(key);
        events_.add(t, EventKind::JointLimit, {{"device", wc_.objects[dr.object].name}, {"joint", jt.name}, {"value", r9(q[j])}});
      } else if (!past) {
        over_limit_.erase(key);
      }
    }
  }

  /// Fast mode: a device that meets something (its part or its load, a collision) goes on in
  /// physics from here (PhysicsWorld::hand_over): whether it is stopped, deflected or pushes
  /// through is not decided kinematically.
  /// True when a device was set back to its pose before the step (the contact's depth is then
  /// that of a pose the run left: not the episode's).
  bool hand_over(double t, const PhysicsContact& c) {
    bool set_back = false;
    if (plan_.settings.mode != SimMode::Fast) return set_back;
    for (auto [o, part] : {std::pair{c.a, c.part_a}, std::pair{c.b, c.part_b}}) {
      int device = part >= 0 ? o : -1;
      const int load = moving_load(o);
      for (const DeviceRun& dr : devices_)
        if (load >= 0 && world_.held(dr.object) == load) device = dr.object;
      // From its plan's pose two steps back, which met nothing (a step finds the contacts of
      // the poses the step before left), not up to two steps' travel into what it met.
      std::optional<Eigen::VectorXd> q_from;
      const double t_back = std::max(0.0, t - 2 * plan_.settings.timestep);
      for (const DeviceRun& dr : devices_)
        if (dr.object == device && world_.on_plan(device)) q_from = dr.track->at(t_back);
      if (device >= 0 && world_.hand_over(device, q_from ? &*q_from : nullptr)) {
        handed_.push_back({wc_.objects[device].name, r9(t), fmt::format("{} meets {}", part_name(c.a, c.part_a), part_name(c.b, c.part_b))});
        if (q_from) {  // the clearances follow it back: its step into what it met is no motion it made
          set_back = true;
          std::vector<Eigen::Isometry3d> X(geometry_.objects[device].X_object_part.size());
          for (size_t k = 0; k < X.size(); ++k) X[k] = world_.part_pose(device, static_cast<int>(k));
          clearances_.set_back(device, t_back, t, X);
          clearances_.move_parts(device, X);
          if (const int held = world_.held(device); held >= 0) {
            clearances_.set_back(held, t_back, t, {world_.pose(held)});
            clearances_.move(held, world_.pose(held));
          }
        }
      }
    }
    return set_back;
  }

  /// A collision episode's physics contact at t, `depth` deep at `point`: the episode lasts to
  /// t, and until the solids were measured its deepest is the physics' deepest contact.
  void grow_collision(CollisionEpisode& ep, double t, double depth, const Eigen::Vector3d* point) {
    ep.file.end = r9(t);
    events_.update(ep.event, "end", ep.file.end);
    if (ep.measured || depth <= ep.depth) return;
    deepest(ep, t, depth, point);
  }

  void deepest(CollisionEpisode& ep, double t, double depth, const Eigen::Vector3d* point) {
    ep.depth = depth;
    ep.file.depth = r9(depth);
    ep.file.deepest_at = r9(t);
    events_.update(ep.event, "depth", ep.file.depth);
    events_.update(ep.event, "deepest_at", ep.file.deepest_at);
    if (point) ep.file.point = std::vector<double>{r9(point->x()), r9(point->y()), r9(point->z())};
    else ep.file.point.reset();
    events_.update(ep.event, "deepest_point", ep.file.point ? nlohmann::ordered_json(*ep.file.point) : nlohmann::ordered_json(nullptr));
  }

  /// A pass through something thin is one episode: ODE finds no contact between a cylinder and
  /// a plate wholly inside it, so the contacts of a drum carried through a 5 mm plate stopped
  /// for 0.24 s in mid-pass and the run said three collisions. An episode whose contacts stopped
  /// less than kApart ago goes on, step by step, while its two solids still overlap by more
  /// than a contact (their parts, for a device's).
  void continue_through_overlap(double t) {
    CollisionWorld& near = clearances_.world();
    for (const auto& [key, index] : collision_of_) {
      CollisionEpisode& ep = collisions_[index];
      const auto& [a, part_a, b, part_b] = key;
      const auto last = last_contact_.find(key);
      // (A device against itself: its parts' solids overlap at their joints by design, and the
      // object against itself is no pair to measure; its episode is its contacts'.)
      if (a < 0 || b < 0 || a == b || last == last_contact_.end() || last->second >= t - 1e-12 || t - last->second > kApart ||
          !still_colliding(a, b))
        continue;
      for (int o : {a, b}) {
        if (geometry_.objects[o].device) {
          motion_.resize(geometry_.objects[o].X_object_part.size());
          for (size_t k = 0; k < motion_.size(); ++k) motion_[k] = world_.part_pose(o, static_cast<int>(k));
          near.move_parts(o, motion_);
        } else {
          near.move(o, world_.pose(o));
        }
      }
      // The device's part of the pair against the other (both objects, when both are devices').
      const bool by_part = part_a >= 0 && part_b < 0;
      const int first = by_part || part_b < 0 ? a : b, second = first == a ? b : a, part = first == a ? part_a : part_b;
      std::vector<char> parts;
      if (part >= 0 && !(part_a >= 0 && part_b >= 0)) {
        parts.assign(geometry_.objects[first].X_object_part.size(), 0);
        parts[part] = 1;
      }
      const std::optional<Proximity> d = near.pair_distance(first, second, parts);
      // Deeper than a contact (a load resting where it landed sinks by micrometres).
      if (!d || d->distance >= -ClearanceTracker::kContact) continue;
      last_contact_[key] = t;
      grow_collision(ep, t, 0, nullptr);  // its end; the depth stays the deepest measured
    }
  }

  /// The contacts the clearance tracker found between two steps, which no step's contacts saw
  /// (a 4 mm blade turning through a 5 mm plate in one step, a sheet carried through a plate at
  /// a 10 ms step: the runs said `ok`): collisions, each its pair's episode then (`between_steps`
  /// when no step saw it), or part of the pair's episode going on then.
  void add_swept() {
    for (const ClearanceTracker::Swept& sw : clearances_.take_swept()) {
      if (!still_colliding(sw.a, sw.b)) continue;
      CollisionEpisode* going = nullptr;
      for (CollisionEpisode& ep : collisions_)
        if (((ep.a == sw.a && ep.b == sw.b) || (ep.a == sw.b && ep.b == sw.a)) && sw.t >= ep.file.start - kApart &&
            sw.t <= ep.file.end + kApart)
          going = &ep;
      if (going) {
        // Found between two steps before the step that opened the episode: it began there
        // (review 23: an episode at 0.0915 s whose deepest pose was at 0.091287 s).
        if (r9(sw.t) < going->file.start) {
          going->file.start = r9(sw.t);
          events_.update(going->event, "t", going->file.start);
        }
        if (sw.depth > going->depth) deepest(*going, sw.t, sw.depth, nullptr);
        if (r9(sw.t) > going->file.end) {
          going->file.end = r9(sw.t);
          events_.update(going->event, "end", going->file.end);
        }
        continue;
      }
      CollisionEpisode ep;
      ep.a = sw.a;
      ep.b = sw.b;
      ep.depth = sw.depth;
      ep.measured = true;  // the solids' own depth at that pose
      ep.file = {part_name(sw.a, sw.part_a), part_name(sw.b, sw.part_b), r9(sw.t), r9(sw.t), r9(sw.depth), r9(sw.t), std::nullopt};
      ep.event = events_.add(sw.t, EventKind::Collision, {{"a", ep.file.a}, {"b", ep.file.b}, {"depth", r9(sw.depth)},
                                                         {"end", r9(sw.t)}, {"deepest_at", r9(sw.t)}, {"between_steps", true}});
      collisions_.push_back(std::move(ep));
    }
  }

  /// Whether the pair's contact would still be a collision: a device's, or a carried load's (once
  /// the load is let go, its contacts are a landing).
  bool still_colliding(int a, int b) const {
    return geometry_.objects[a].device || geometry_.objects[b].device || moving_load(a) >= 0 || moving_load(b) >= 0;
  }

  /// At the trajectory rate: each collision still going on, as deep as the two objects' solids
  /// are into each other now: the length of the shortest push that separates them. Once measured
  /// this is the episode's depth (a physics contact's depth is one contact's, along its normal:
  /// ODE said 0.8 mm at a forklift's first touch of a drum, and 1.38 m for a drum wholly inside
  /// its body that a 0.80 m push frees).
  void grow_collisions_by_distance(double t) {
    for (CollisionEpisode& ep : collisions_) {
      // A device against itself is measured by its contacts only (the object against itself
      // read 0.2 m deep, the whole arm's overlap at its joints, for a touch of its links).
      if (ep.a < 0 || ep.b < 0 || ep.a == ep.b || t - ep.file.end > kApart) continue;
      const std::optional<double> d = clearances_.distance(ep.a, ep.b);
      if (!d || *d >= 0) continue;
      if (!ep.measured || -*d > ep.depth) deepest(ep, t, -*d, nullptr);
      ep.measured = true;
      if (*d < -ClearanceTracker::kContact && r9(t) > ep.file.end && still_colliding(ep.a, ep.b)) {  // still into each other
        ep.file.end = r9(t);
        events_.update(ep.event, "end", ep.file.end);
      }
    }
  }

  /// When the move that set released object `o` down began: the last move of the device that
  /// released it, up to the release (it was lowered onto what it lands on while still held).
  double set_down_from(int o) const {
    auto when = released_when_.find(o);
    auto by = released_by_.find(o);
    if (when == released_when_.end() || by == released_by_.end()) return 0;
    double from = when->second;
    for (const PlannedStep& ps : plan_.steps) {
      if (ps.kind == StepKind::Release && ps.device == by->second && std::abs(ps.start - when->second) <= plan_.settings.timestep / 2)
        break;  // the moves after it start at the same instant
      if (ps.device == by->second && is_move(ps.kind)) from = ps.start;
    }
    return from;
  }

  /// When the move that lifts what device `d` grasps at `t` ends: its first move from then on.
  double lift_end(int d, double t) const {
    for (const PlannedStep& ps : plan_.steps)
      if (ps.device == d && is_move(ps.kind) && ps.start >= t - plan_.settings.timestep / 2) return ps.end;
    return t;
  }

  static bool is_move(StepKind kind) { return kind == StepKind::MoveTo || kind == StepKind::MoveJoints; }

  /// At the trajectory rate: a tool that lags its plan by more than kTrackingTolerance is an
  /// event, once an episode (until it is back within half of it), at its start; its `deviation`
  /// is the largest of the episode (a blocked move that misses by 0.5 m says 0.5 m, not the 5 mm
  /// it first passed) and `largest_at` when that was.
  void check_tracking(double t) {
    for (DeviceRun& dr : devices_) {
      // Off its plan's position, or its orientation (a wrist lagging 63 deg behind its plan with
      // the tool point on its axis went unseen).
      const Lag lag = lag_of(dr, t);
      const double over = lag.over();
      if (over > 1 && !dr.lagging) {
        dr.lagging = true;
        dr.largest_lag = over;
        dr.lag_event = events_.add(t, EventKind::TrackingError, {{"device", wc_.objects[dr.object].name}, {"deviation", r9(lag.distance)},
                                                                 {"turn", r9(lag.turn * 180 / kPi)}, {"largest_at", r9(t)}});
      } else if (dr.lagging && over > dr.largest_lag) {
        dr.largest_lag = over;
        events_.update(dr.lag_event, "deviation", r9(lag.distance));
        events_.update(dr.lag_event, "turn", r9(lag.turn * 180 / kPi));
        events_.update(dr.lag_event, "largest_at", r9(t));
      } else if (over < 0.5) {
        dr.lagging = false;
      }
    }
  }

  /// Where everything is now, for frames.
  ScenePose scene_pose() const {
    ScenePose p = ScenePose::of(geometry_);
    for (const DeviceRun& dr : devices_) {
      const Eigen::Isometry3d X_object_world = geometry_.objects[dr.object].X_world_object.inverse();
      auto& parts = p.X_object_part[dr.object];
      for (size_t k = 0; k < parts.size(); ++k) parts[k] = X_object_world * world_.part_pose(dr.object, static_cast<int>(k));
    }
    for (size_t o = 0; o < wc_.objects.size(); ++o)
      if (world_.dynamic(static_cast<int>(o))) p.X_world_object[o] = world_.pose(static_cast<int>(o));
    if (!absent_.empty()) {
      p.hidden.assign(wc_.objects.size(), 0);
      for (int o : absent_) p.hidden[o] = 1;
    }
    return p;
  }

  /// The object and the containers (rooms): spaces, as the physics has them, not clearances.
  /// Other parents (an arm's pedestal, a drum's pallet) are solids like any other.
  std::vector<int> chain(int o) const {
    if (containers_.empty())  // (found once: asked of each device and load at every sample and glide)
      for (size_t k = 0; k < wc_.objects.size(); ++k)
        if (wc_.types[wc_.objects[k].type].container) containers_.push_back(static_cast<int>(k));
    std::vector<int> out = {o};
    for (int k : containers_)
      if (k != o) out.push_back(k);
    return out;
  }
  mutable std::vector<int> containers_;  ///< chain()'s: the vault's containers (none: not found yet, or none)
  std::vector<std::vector<std::vector<Eigen::Isometry3d>>> glide_poses_;  ///< glide_clear()'s: per device, per sub-step, per part

  /// The objects the plan moves: its devices, what they grasp and what stands on that (riders
  /// were not re-checked: a drum lifted on a pallet to 2.6 m passed a 1.2 m lift rule).
  std::set<int> movers(const Plan& plan) {
    std::set<int> out;
    for (const Track& t : plan.tracks) out.insert(t.object);
    std::set<int> arriving;  // a campaign's loads, all at their spots until the run sets them away
    for (const auto& [o, at] : plan.arrivals) arriving.insert(o);
    for (const PlannedStep& ps : plan.steps)
      if (ps.kind == StepKind::Grasp) {
        out.insert(ps.object);
        // What stands on a load that arrives arrives too (a load of its own): not the loads
        // that will arrive after it at the same spot, each one measured against the others
        // (eight pallets' meshes, 5 s of a campaign's 12).
        if (!arriving.count(ps.object))
          for (int k : riders(ps.object)) out.insert(k);
      }
    return out;
  }
  /// The devices the plan moves, in its order.
  static std::vector<int> tracked(const Plan& plan) {
    std::vector<int> out;
    for (const Track& t : plan.tracks) out.push_back(t.object);
    return out;
  }

  /// Places the run's state now in the live model (device parts, moved objects, their joint and
  /// pose values) and, with `clearance`, in the clearance tracker; returns the loads held.
  std::vector<int> pose_live(bool clearance) {
    std::vector<int> loads;
    for (const DeviceRun& dr : devices_) {
      const Device& m = *geometry_.objects[dr.object].device;
      const Eigen::Isometry3d& X_world_object = geometry_.objects[dr.object].X_world_object;
      const Eigen::Isometry3d X_object_world = X_world_object.inverse();
      std::vector<Eigen::Isometry3d>& X_object_part = live_parts_;
      X_object_part.resize(geometry_.objects[dr.object].X_object_part.size());
      for (size_t k = 0; k < X_object_part.size(); ++k) X_object_part[k] = compose(X_object_world, world_.part_pose(dr.object, static_cast<int>(k)));
      if (clearance) {
        std::vector<Eigen::Isometry3d>& X_world_part = live_world_parts_;
        X_world_part.resize(X_object_part.size());
        for (size_t k = 0; k < X_object_part.size(); ++k) X_world_part[k] = compose(X_world_object, X_object_part[k]);
        clearances_.move_parts(dr.object, X_world_part);
      }
      repose(live_.objects[dr.object], X_world_object, &X_object_part);
      Eigen::VectorXd q = world_.joints(dr.object);
      const Object& obj = wc_.objects[dr.object];
      for (int j = 0; j < m.dof(); ++j) live_values_[obj.first_slot + kFirstAttributeSlot + m.joint(j).attribute] = q[j];
      if (world_.held(dr.object) >= 0) loads.push_back(world_.held(dr.object));
    }
    live_posed_.resize(wc_.objects.size());
    for (size_t o = 0; o < wc_.objects.size(); ++o) {
      if (!world_.dynamic(static_cast<int>(o))) continue;
      const Eigen::Isometry3d& X = world_.pose(static_cast<int>(o));
      if (clearance) clearances_.move(static_cast<int>(o), X);
      const Object& obj = wc_.objects[o];
      const Eigen::Isometry3d X_world_parent =
          obj.parent >= 0 ? live_.objects[obj.parent].X_world_object * live_.objects[o].X_parent_at : Eigen::Isometry3d::Identity();
      // Where it was posed last, under the parent where it was: nothing to redo (a store's 143
      // drums at rest, posed again at each sample, were a tenth of a fast run's time).
      LivePosed& last = live_posed_[o];
      if (last.valid && last.X.matrix() == X.matrix() && last.parent.matrix() == X_world_parent.matrix()) continue;
      last = {true, X, X_world_parent};
      repose(live_.objects[o], X);
      Eigen::Isometry3d local = X_world_parent.inverse() * X;
      Eigen::Vector3d rpy = rotation_to_rpy(local.linear());
      for (int k = 0; k < 3; ++k) {
        live_values_[obj.first_slot + kLocationSlot + k] = local.translation()[k];
        live_values_[obj.first_slot + kOrientationSlot + k] = rpy[k];
      }
    }
    return loads;
  }

  /// At a physics step between the samples: the bounds and expressions that read the motion, and
  /// the `inside` rules where the bound from their objects' travel no longer clears (the live
  /// model posed once, and only when one of them needs it).
  void recheck_between_samples(double t) {
    bool posed = false;
    auto pose = [&] {
      if (!posed) pose_live(false);
      posed = true;
    };
    if (rechecks_.every_step()) {
      pose();
      rechecks_.check_step(t, live_, live_values_, events_);
    }
    if (rechecks_.watches_inside()) rechecks_.check_inside_step(t, clearances_, pose, live_, live_values_, events_);
  }

  /// At the trajectory rate: clearances between what moves and everything else, and the
  /// constraints that depend on the motion.
  void observe(double t) {
    const std::vector<int> loads = pose_live(true);
    // Each device's moving parts against everything but the loads it handles (the one it holds,
    // the next it takes, the last it let go): those it may touch, not go into.
    for (const DeviceRun& dr : devices_) {
      std::vector<int> skip = chain(dr.object);
      for (int o : handled(dr.object, t)) {
        skip.push_back(o);
        if (o != world_.held(dr.object)) clearances_.measure_penetration(t, dr.object, o);
      }
      clearances_.measure(t, dr.object, skip, dr.moving_parts);
    }
    // Each carried load and what rides on it, against everything but the stack itself (a drum
    // resting on its pallet is no clearance: the summary said -1.6e-6 m for every lifted pallet
    // and hid a drum passing 55 mm under a beam), the device holding it, and the devices about
    // to take or just letting go of one of them (measured from their side, tool included). What
    // it was lifted from is measured: excused from the grasp until they part, and never again
    // (a drum lowered through the drum it then landed on said 0.02 m).
    for (int o : loads) {
      std::vector<int> stack = {o};
      for (const auto& [rider, load] : rider_of_)
        if (load == o && !held_anywhere(rider)) stack.push_back(rider);
      for (int moving : stack) {
        std::vector<int> skip = chain(moving);
        skip.insert(skip.end(), stack.begin(), stack.end());
        for (const DeviceRun& dr : devices_) {
          const std::vector<int> loads_of = handled(dr.object, t);
          if (world_.held(dr.object) == o || std::find(loads_of.begin(), loads_of.end(), moving) != loads_of.end())
            skip.push_back(dr.object);
        }
        clearances_.measure(t, moving, skip);
      }
    }
    add_swept();
    grow_collisions_by_distance(t);
    check_tracking(t);
    check_riders(t);
    if (rechecks_.any()) rechecks_.check(t, live_, live_values_, events_, &clearances_);
    clearances_.next_interval(t);
  }

  /// The loads a device's tool deals with around time t: the one it holds, the next it will
  /// grasp (from one timestep before the grasp), and the last it released.
  std::vector<int> handled(int device, double t) const {
    int next = -1, last = -1;
    for (const PlannedStep& ps : plan_.steps) {
      if (ps.device != device || ps.object < 0) continue;
      if (ps.kind == StepKind::Grasp && ps.start >= t - plan_.settings.timestep && next < 0) next = ps.object;
      if (ps.kind == StepKind::Release && ps.start <= t + plan_.settings.timestep / 2) last = ps.object;  // at its own sample too
    }
    std::vector<int> out;
    for (int o : {world_.held(device), next, last})
      if (o >= 0) out.push_back(o);
    return out;
  }

  /// Whether a released object has moved sideways by more than kTrackingTolerance since its
  /// release: a tool still touching it then is pushing it, a collision (forks backing out of a
  /// pallet they had set down dragged it 127 mm, or flung it off a rack, and the run said ok).
  bool pushed_since_release(int o) const {
    auto at = released_at_.find(o);
    if (at == released_at_.end() || held_anywhere(o)) return false;
    return (world_.pose(o).translation() - at->second).head<2>().norm() > kTrackingTolerance;
  }

  /// An object set down (released, or standing on a load when that was released) that came to
  /// rest more than kGraspReach sideways, or more than kSetDownDrop lower, than where it was set
  /// down did not stay where the operation put it: it fell (a drum released on a rack level
  /// without a beam under it fell 0.52 m to the floor, and the run said ok), rolled or slid off.
  /// A `displaced` event; the plan's picture of the scene no longer holds either.
  /// `fall` is how far its lowest point went down (a drum set down tilted that rocked upright
  /// raised and lowered its origin, but fell nowhere).
  void check_displaced(double t, int o, const Eigen::Vector3d& p) {
    auto at = set_down_at_.find(o);
    if (at == set_down_at_.end()) return;
    const Eigen::Vector3d move = p - at->second.position;
    const double fall = std::max(0.0, at->second.bottom - bottom_of(o));
    // Higher than it was set down is off its target too: pushed out of what it was lowered
    // into, it rested on top of another drum 0.85 m up and the run said nothing.
    const double rise = std::max(0.0, bottom_of(o) - at->second.bottom);
    // (At the threshold, a micrometre of sinking into what it rests on is no fall: a drum let go
    // exactly 50 mm up fell 0.050000206 m and was displaced; review 22.)
    if (move.head<2>().norm() <= kGraspReach && fall <= kSetDownDrop + kTouchTolerance && rise <= kGraspReach) return;
    if (!displaced_.insert(o).second) return;  // once an object
    const Eigen::Vector3d& from = at->second.position;
    events_.add(t, EventKind::Displaced, {{"object", wc_.objects[o].name}, {"from", {r9(from.x()), r9(from.y()), r9(from.z())}},
                                          {"to", {r9(p.x()), r9(p.y()), r9(p.z())}}, {"distance", r9(move.norm())},
                                          {"fall", r9(fall)}, {"rise", r9(rise)}});
  }

  /// At the end of the run, a released object that a device's part still holds up (pushes
  /// sideways or up with more than kProppedShare of its weight) was not set down: it leans on what will move away
  /// (a drum set down 1 deg past its tipping angle, the gripper's fingers against its lid, stood
  /// at rest and the run said ok). A `propped` event.
  void check_propped(double t) {
    for (int o : loose()) {
      // Pressing it down holds nothing up: only the sideways and upward push counts.
      Eigen::Vector3d F = world_.device_force(o);
      F.z() = std::max(F.z(), 0.0);
      // Held up from below by a device that cannot lower it (an AGV's deck, a cart's bed) is
      // where it was set down, not propped: such a device carries what it carries. Standing on
      // it, what it pushes sideways is the friction of that support, not a prop (a pallet with
      // two drums at rest on an AGV's deck read 0.7 % of its weight in one run and 1.2 % in
      // another, either side of the threshold: solver noise).
      if (const int by = world_.device_pushing(o); by >= 0 && !can_lower(by)) {
        F.z() = 0;
        const std::vector<int> under = stands_on(o);
        if (std::find(under.begin(), under.end(), by) != under.end()) F.setZero();
      }
      const double weight = world_.mass(o) * kStandardGravity;
      if (world_.device_pushing(o) < 0 || F.norm() <= kProppedShare * weight) continue;
      events_.add(t, EventKind::Propped, {{"object", wc_.objects[o].name}, {"by", wc_.objects[world_.device_pushing(o)].name},
                                          {"force", r9(F.norm())}, {"share", r9(F.norm() / weight)}});
    }
  }

  /// Whether some joint of device `d` moves its tool up or down where it is now (a lift, a
  /// hoist, an arm), unlike an AGV or a cart whose joints only drive and turn it.
  bool can_lower(int d) const {
    const Device& m = *geometry_.objects[d].device;
    const Eigen::VectorXd q = world_.joints(d);
    const double z = m.tool_pose(q).translation().z();
    for (int j = 0; j < m.dof(); ++j) {
      Eigen::VectorXd q1 = q;
      q1[j] += 1e-3;
      if (std::abs(m.tool_pose(q1).translation().z() - z) > 1e-9) return true;
    }
    return false;
  }

  /// The height of an object's lowest point where the physics has it now.
  double bottom_of(int o) const {
    ObjectGeometry g = geometry_.objects[o];
    repose(g, world_.pose(o), nullptr);
    return g.bbox_world.isEmpty() ? world_.pose(o).translation().z() : g.bbox_world.min().z();
  }

  /// The run fails here: it stops with what it has, and says why.
  void stop(EventKind kind, const std::string& message) {
    failed_ = true;
    stopped_by_ = event_kind_name(kind);
    stop_message_ = message;
  }

  /// How the run leaves the vault: every object where it stands, devices at their last joint
  /// values, the loads that never arrived gone.
  FinalState final_state() {
    FinalState end;
    end.t = t_end_;
    const size_t n = wc_.objects.size();
    end.gone.assign(n, 0);
    end.moved.assign(n, 0);
    end.attributes.resize(n);
    for (size_t o = 0; o < n; ++o) {
      const Eigen::Isometry3d& compiled = geometry_.objects[o].X_world_object;
      end.X_world.push_back(geometry_.objects[o].device ? compiled : world_.pose(static_cast<int>(o)));
      end.moved[o] = (end.X_world.back().matrix() - compiled.matrix()).cwiseAbs().maxCoeff() > 1e-12;
    }
    for (int o : absent_) end.gone[o] = 1;
    // What came to rest on something sinks into it by the contact solver's softness (a drum
    // 1.2 µm into its rack's beam): final.yaml has it touching, lifted out of a sink of up to
    // 1 mm (so that the vault it writes keeps its no_overlap rules).
    CollisionWorld& near = clearances_.world();
    for (size_t o = 0; o < n; ++o) {
      if (!end.moved[o] || end.gone[o] || geometry_.objects[o].device || !world_.dynamic(static_cast<int>(o))) continue;
      Eigen::Isometry3d X = end.X_world[o];
      for (int k = 0; k < 3; ++k) {
        near.move(static_cast<int>(o), X);
        double d = INFINITY;
        for (const Proximity& p : near.proximity(static_cast<int>(o), chain(static_cast<int>(o)), 1e-3))
          if (!geometry_.objects[p.other].device) d = std::min(d, p.distance);  // what it rests on, not a device's part
        d = std::min(d, near.lowest(static_cast<int>(o)) - world_.floor_z());  // the floor is no object of the collision world
        if (!(d < 0 && d > -1e-3)) break;
        X.translation().z() += -d + 1e-9;
      }
      near.move(static_cast<int>(o), end.X_world[o]);
      end.X_world[o] = X;
    }
    for (const DeviceRun& dr : devices_) {
      const Device& m = *geometry_.objects[dr.object].device;
      // Where the run left it, not where its plan had it then (a campaign stopped by a grasp its
      // tool missed, held back by what was in the way, had its device written at the planned
      // grasp pose, inside the obstacle).
      Eigen::VectorXd q = world_.joints(dr.object);
      const Object& obj = wc_.objects[dr.object];
      const double* attributes = &wc_.values[obj.first_slot + kFirstAttributeSlot];
      auto within_limits = [&](Eigen::VectorXd& joints) {  // (one held back stands a hair past them)
        for (int k = 0; k < m.dof(); ++k) {
          const AttributeDef& def = wc_.types[obj.type].attributes[m.joint(k).attribute];
          joints[k] = std::clamp(joints[k], def.lower(attributes), def.upper(attributes));
        }
      };
      within_limits(q);
      // Held back by what it pressed on (a gripper lowered onto a table), it sinks into that by
      // the contact solver's softness as a load does (11 µm, and final.yaml failed its own
      // vault's no_overlap): backed off against the way its motors drove it, out of a sink of
      // up to 1 mm.
      const Eigen::VectorXd push = dr.track->at(t_end_) - q;
      if (push.norm() > 1e-9) {
        const Eigen::Isometry3d& X_world_object = geometry_.objects[dr.object].X_world_object;
        std::vector<int> skip = chain(dr.object);
        if (world_.held(dr.object) >= 0) skip.push_back(world_.held(dr.object));
        std::vector<Eigen::Isometry3d> X;
        auto sink = [&](const Eigen::VectorXd& joints) {
          X.clear();
          for (const Eigen::Isometry3d& P : m.part_poses(joints)) X.push_back(X_world_object * P);
          near.move_parts(dr.object, X);
          double d = INFINITY;
          for (const Proximity& p : near.proximity(dr.object, skip, 1e-3))
            if (!geometry_.objects[p.other].device) d = std::min(d, p.distance);
          return d;
        };
        Eigen::VectorXd backed = q;
        double d = sink(backed);
        for (int k = 0; k < 10 && d < 0 && d > -1e-3; ++k) {
          backed -= push.normalized() * (-d + 1e-9);
          within_limits(backed);
          d = sink(backed);
        }
        if (d >= 0) q = backed;
        X.clear();
        for (int p = 0; p < static_cast<int>(m.parts.size()); ++p) X.push_back(world_.part_pose(dr.object, p));
        near.move_parts(dr.object, X);
      }
      for (int k = 0; k < m.dof(); ++k) end.attributes[dr.object].emplace_back(m.joint(k).attribute, q[k]);
    }
    return end;
  }

  RunSummary finish(double t_end) {
    t_end_ = t_end;
    clearances_.finish();  // the pieces of motion left to halve
    add_swept();
    if (rechecks_.any()) rechecks_.finish(clearances_, events_);
    RunSummary s;
    // A run that stopped has no cycle time: its cycle was not done.
    s.cycle_time = failed_ || !unfinished_.empty() ? std::numeric_limits<double>::quiet_NaN() : end_;
    s.unfinished = unfinished_;
    s.stopped_by = stopped_by_;
    s.stopped_at = t_end;
    s.stop_message = stop_message_;
    s.simulated = t_end;
    s.events = events_.size();
    s.collisions = events_.count(EventKind::Collision);
    bool violations = s.collisions > 0 || events_.count(EventKind::JointLimit) || events_.count(EventKind::TrackingError) ||
                      events_.count(EventKind::LoadShifted) || events_.count(EventKind::NotAtRest) ||
                      events_.count(EventKind::Displaced) || events_.count(EventKind::Propped) || events_.count(EventKind::KeepOut) ||
                      rechecks_.failures() > 0;
    s.interrupted = interrupted_;
    s.status = failed_ ? RunStatus::Failed : violations ? RunStatus::Violations : RunStatus::Ok;
    if (!plan_.jobs.empty()) {
      RunReach reach;
      reach.ended = ended_;
      if (failed_) reach.stopped_at = t_end;
      reach.ended_at = t_end;
      reach.stop_message = stop_message_.empty() ? stopped_by_ : stop_message_;
      reach.job_failures = run_failures_;
      reach.out_at = out_at_;
      for (size_t o = 0; o < wc_.objects.size(); ++o) {
        const bool solid = !geometry_.objects[o].device && !wc_.types[wc_.objects[o].type].container && !geometry_.objects[o].shapes.empty();
        if (solid) reach.positions.emplace_back(world_.pose(static_cast<int>(o)).translation());
        else reach.positions.emplace_back();
      }
      campaign_ = campaign_outcome(wc_, plan_, reach);
      s.campaign = campaign_->figures;
      // A campaign in which a job failed has failed, though it went on (on_failure: continue),
      // and, as a run that stopped, has no cycle time: its cycle was not done (the makespan is
      // its figure).
      if (campaign_->figures.failed > 0) {
        s.status = RunStatus::Failed;
        s.cycle_time = std::numeric_limits<double>::quiet_NaN();
      }
    }
    return s;
  }

  nlohmann::ordered_json summary_json(const RunSummary& s) const {
    RunSummaryFile f;
    f.scenario = options_.scenario_name;
    f.vault = wc_.name;
    f.status = run_status_name(s.status);
    f.mode = sim_mode_name(plan_.settings.mode);
    f.handed_to_physics = handed_;
    f.fast = {glides_, steps_, world_.dynamics_steps()};
    if (std::isfinite(s.cycle_time)) f.cycle_time = r9(s.cycle_time);
    f.simulated_time = r9(s.simulated);
    if (!s.stopped_by.empty()) f.stopped = RunSummaryFile::Stopped{s.stopped_by, r9(s.stopped_at), s.stop_message};
    // A run that stopped early: steps it had not begun or not finished by then have no start or
    // end (null), never a planned time the run did not reach.
    const double reached = s.stopped_by.empty() ? std::numeric_limits<double>::infinity() : s.stopped_at;
    auto when = [&](double t) { return t <= reached + 1e-9 ? std::optional(r9(t)) : std::nullopt; };
    for (size_t i = 0; i < plan_.steps.size(); ++i) {
      const PlannedStep& ps = plan_.steps[i];
      RunSummaryFile::Step st;
      st.index = ps.index;
      st.action = step_kind_name(ps.kind);
      if (ps.device >= 0) st.device = wc_.objects[ps.device].name;
      if (ps.object >= 0) st.object = wc_.objects[ps.object].name;
      if (ps.job >= 0) st.job = job_label(ps.job);
      // A step of a job that failed in the run: never begun, or begun and never finished.
      const bool skipped = i < skipped_.size() && skipped_[i];
      st.start = skipped && !started_[i] ? std::nullopt : when(ps.start);
      st.end = plan_.failed_at(ps) || skipped ? std::nullopt : when(ps.end);  // it began and never finished
      if (auto sb = short_by_.find(i); sb != short_by_.end()) st.short_by = r9(sb->second);
      if (auto tb = turned_by_.find(i); tb != turned_by_.end()) st.turned_by = r9(tb->second);
      f.steps.push_back(std::move(st));
    }
    for (const PlannedStep& ps : plan_.not_begun) {  // after the failure
      RunSummaryFile::Step st;
      st.index = ps.index;
      st.action = step_kind_name(ps.kind);
      if (ps.device >= 0) st.device = wc_.objects[ps.device].name;
      if (ps.object >= 0) st.object = wc_.objects[ps.object].name;
      if (ps.job >= 0) st.job = job_label(ps.job);
      f.steps.push_back(std::move(st));
    }
    for (const DeviceRun& dr : devices_) {
      const Device& m = *geometry_.objects[dr.object].device;
      RunSummaryFile::DeviceFigures d;
      // Totals per joint kind: degrees and metres never add up.
      double revolute = 0, prismatic = 0;
      bool any_revolute = false, any_prismatic = false;
      for (int k = 0; k < m.dof(); ++k) {
        bool turns = m.joint(k).type == JointType::Revolute;
        d.joint_travel.emplace_back(m.joint(k).name, r9(turns ? dr.travel[k] * kRad : dr.travel[k]));
        (turns ? revolute : prismatic) += turns ? dr.travel[k] * kRad : dr.travel[k];
        (turns ? any_revolute : any_prismatic) = true;
      }
      if (any_revolute) d.revolute_deg = r9(revolute);
      if (any_prismatic) d.prismatic_m = r9(prismatic);
      d.tool_path_length = r9(dr.path);
      f.devices.emplace_back(wc_.objects[dr.object].name, std::move(d));
    }
    // The closest approach, or the deepest penetration of any collision: negative whenever
    // something went into something.
    f.min_clearance = clearances_.closest();
    for (const CollisionEpisode& ep : collisions_) {
      f.collisions.push_back(ep.file);
      if (!f.min_clearance || -ep.file.depth < f.min_clearance->distance)
        f.min_clearance = RunSummaryFile::Clearance{-ep.file.depth, ep.file.a, ep.file.b, ep.file.deepest_at};
    }
    for (size_t k = 0; k < kEventKindNames.size(); ++k)
      if (size_t n = events_.count(static_cast<EventKind>(k))) f.events.emplace_back(std::string(kEventKindNames[k]), n);
    if (const SolverMessages& m = world_.solver_messages(); m.count > 0)
      f.physics_messages = RunSummaryFile::PhysicsMessages{m.count, r9(m.first_at), m.first};
    if (options_.inputs) {
      for (const InputFile& in : options_.inputs->files) f.inputs.emplace_back(in.path, in.sha256);
      f.inputs_not_in_resolved = options_.inputs->not_copied;
    }
    if (campaign_) f.campaign = campaign_->figures;
    f.sscs_version = SSCS_VERSION;
    return f.to_json();
  }

  const Workcell& wc_;
  const GeometryModel& geometry_;
  const Plan& plan_;
  const RunOptions& options_;
  PhysicsWorld world_;
  std::vector<DeviceRun> devices_;
  EventLog events_;
  std::map<std::tuple<int, int, int, int>, double> last_contact_;
  std::map<int, bool> released_;  // released objects: landed yet?
  std::map<int, int> rider_of_;   // an object riding on a held load -> that load
  std::vector<Eigen::Isometry3d> motion_;  // follow_motion's scratch
  std::vector<Eigen::Isometry3d> live_parts_, live_world_parts_;  // pose_live's scratch
  /// Fast mode: per device, how near the nearest thing stood to what it moves when last looked
  /// (glide_clear), and how much of that the glides since may have taken (each glide's travel of
  /// all the devices, glide_all_); valid while `changes` is changes_: no physics step, step
  /// start or end, or arrival since.
  struct Room {
    long changes = -1;
    double clear = 0, spent = 0;
  };
  std::vector<Room> room_;
  long changes_ = 0;
  double glide_all_ = 0;
  /// Per object: where pose_live() last posed it in the live model, and its parent's frame then.
  struct LivePosed {
    bool valid = false;
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity(), parent = Eigen::Isometry3d::Identity();
  };
  std::vector<LivePosed> live_posed_;
  struct OwnMemo {
    int load = -1;
    std::vector<Eigen::Isometry3d> parts;  // the device's parts where own_distance last measured
    double distance = INFINITY;
  };
  std::map<int, OwnMemo> own_memo_;  // per device: its load's distance to its other parts
  std::map<int, int> rode_on_;    // every object that rode on a load -> that load (also after the release)
  std::map<int, Eigen::Vector3d> released_at_;  // a released object's position when released
  std::map<int, double> released_when_;         // and when
  std::map<int, int> released_by_;              // and by which device
  std::vector<CollisionEpisode> collisions_;
  std::map<std::tuple<int, int, int, int>, size_t> collision_of_;  // contact key -> its episode
  struct SetDown {
    Eigen::Vector3d position;  // its origin
    double bottom = 0;         // the height of its lowest point
  };
  std::map<int, SetDown> set_down_at_;
  std::map<int, double> lifted_from_;  // a grasped object: the height of its lowest point when grasped
  std::set<int> risen_;                // grasped objects that have risen kSupportGap above it since  // where an object was set down (released, or its load was)
  std::map<int, Eigen::Isometry3d> X_load_rider_;  // a rider's pose on its load when the load was grasped
  std::map<int, std::pair<size_t, double>> shifted_;  // rider -> its load_shifted event, the largest shift
  std::map<int, Eigen::Isometry3d> rested_;  // released objects at rest -> where they came to rest
  std::set<int> displaced_;                  // objects with a displaced event
  std::set<std::pair<int, int>> over_limit_;
  bool failed_ = false;
  std::string stopped_by_, stop_message_;
  /// A failure this run found that its plan did not know (on_failure: continue): the run stopped
  /// there, to be planned again and run anew.
  std::optional<FoundInRun> replan_;
  /// Moves that ended with the tool still off their target (by plan position: how far), and what
  /// the first says: the run has no cycle time.
  std::map<size_t, double> short_by_;
  std::map<size_t, double> turned_by_;  ///< deg, of the moves short_by_ has that ended turned off
  std::string unfinished_;
  bool interrupted_ = false;
  std::vector<RunSummaryFile::HandOver> handed_;  // fast mode: devices that went on in physics
  long glides_ = 0;                               // fast mode: glides between ticks
  long glide_backoff_ = 1, next_glide_look_ = 0;  // fast mode: ticks to the next look for a glide after a refusal
  long steps_ = 0;                                // physics steps taken
  std::vector<char> started_, ended_;  // per step
  std::vector<char> skipped_;          // per step: never to run or end, its job failed in the run
  std::vector<RunReach::JobFailure> run_failures_;  // jobs the run failed, going on (on_failure: continue)
  std::map<int, double> out_at_;       // their devices: out from then
  std::deque<Track> held_tracks_;      // their devices' tracks from then: standing still
  size_t first_open_ = 0;              // steps before it have ended
  bool steps_in_order_ = true;         // the plan's steps in order of start (a break in the look for what is due)
  std::vector<std::pair<double, int>> arrivals_;  // a campaign's: (when, load), in time order
  size_t next_arrival_ = 0;
  std::set<int> absent_;               // loads not arrived yet
  size_t job_failures_seen_ = 0;       // a campaign's job failures with their events
  std::optional<CampaignOutcome> campaign_;  // a campaign's jobs and figures, once the run is over
  double t_end_ = 0;                   // when the run ended
  double end_ = 0;                     // when the last step to run ends (the plan's end, less a device out's)
  double settle_until_ = -1;           // after the last step: when loose objects must rest by
  std::chrono::steady_clock::time_point wall_start_;
  size_t current_step_ = 0;
  int frames_ = 0;
  std::string current_action_;
  ClearanceTracker clearances_;
  std::set<std::pair<int, int>> supports_;  // (load, what it was lifted from or landed on)
  TrajectoryRecorder recorder_;
  // Constraint re-checks: the workcell's geometry and slot values as the motion has them now.
  GeometryModel live_;
  std::vector<double> live_values_;
  ConstraintRechecks rechecks_;
};

}  // namespace

std::string run_work_dir(const RunOptions& options) {
  return temp_dir_for(options.out_dir.empty() ? options.bundle : options.out_dir);
}

Expected<RunSummary> run_simulation(const Workcell& wc, const GeometryModel& geometry, const Plan& plan, const RunOptions& options) {
  // A campaign going on after a failure its run finds (a grasp missed) is planned again knowing
  // it and run anew, once for each such failure: the device's queued jobs go to other devices.
  const Plan* current = &plan;
  std::optional<Plan> again;
  for (;;) {
    Run run(wc, geometry, *current, options);
    RunSummary summary;
    try {
      summary = run.run();
    } catch (const PhysicsFailure& e) {
      std::error_code ec;
      fs::remove_all(work_dir(options), ec);
      return Unexpected{std::string(e.what())};
    }
    if (const std::optional<FoundInRun>& found = run.replan()) {
      std::vector<FoundInRun> known = current->found;
      known.push_back(*found);
      std::optional<Plan> next = current->replan(known);
      if (!next) return Unexpected{"the campaign could not be planned again after a failure its run found"};
      again = std::move(next);
      current = &*again;
      if (options.on_restart) options.on_restart(*current);
      continue;
    }
    std::string error;
    if (!summary.interrupted && options.before_write) error = options.before_write();
    if (!summary.interrupted && error.empty() && (!options.out_dir.empty() || !options.bundle.empty())) error = run.write(summary);
    std::error_code ec;
    if (summary.interrupted || !error.empty()) fs::remove_all(work_dir(options), ec);
    if (!error.empty()) return Unexpected{error};
    return summary;
  }
}

}  // namespace sscs
