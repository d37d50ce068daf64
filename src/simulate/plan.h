#pragma once
/// The planning half of `simulate`: a scenario resolved against its compiled vault into timed,
/// commanded joint trajectories per device, with grasp and release times. Planning is kinematic
/// and deterministic; the physics stage then drives the devices along these trajectories.
///
/// Problems in the file (unknown device, joint or object, a value past a joint limit, a grasp
/// while the tool is away from the object, a release with nothing held) are input errors.
/// Problems of the motion itself (an unreachable target, a linear path through a singularity)
/// end the plan with a failure event at that step: the run fails, it does not hang.
#include <algorithm>
#include <iterator>
#include <memory>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "compile/workcell.h"
#include "core/diagnostics.h"
#include "geometry/geometry.h"
#include "core/written.h"
#include "simulate/events.h"
#include "simulate/profile.h"

namespace sscs {

/// How close a device's tool must be to an object's bounds to grasp it (m): judged when the
/// plan is made and again when the run takes it, where the physics has it then.
constexpr double kGraspReach = 0.02;

/// How a run moves things (campaign-format.md, "Modes"): everything in ODE at the timestep, or
/// devices and what they carry kinematically with physics only where it decides something.
enum class SimMode : uint8_t { Physics, Fast };
const char* sim_mode_name(SimMode m);

struct SimSettings {
  SimMode mode = SimMode::Physics;
  double timestep = 1e-3;  ///< s
  double limit = 60;       ///< s of simulated time
  double check_tolerance = 1e-4;  ///< m: spatial re-checks during the run hold within this (contacts sink)
  double rate = 100;       ///< trajectory rows per simulated second
  bool gravity = true;
  bool frames = false;
  int fps = 30, width = 1280, height = 720;
};

/// A piece of a device's commanded trajectory.
struct Segment {
  double t0 = 0, t1 = 0;
  std::optional<JointMove> joint;  ///< a joint-space move
  /// A linear tool path: joint waypoints at path parameters s in [0, 1], and the trapezoid
  /// that maps time to s.
  std::vector<std::pair<double, Eigen::VectorXd>> waypoints;
  Trapezoid timing;
  Eigen::VectorXd q_end;
  Eigen::VectorXd at(double t) const;
  /// Widens [lo, hi] to every joint value of the segment over [a, b] (within it): each joint's
  /// trapezoid, and a path's time-to-s, are monotone, so the values at a and b and at the
  /// path's waypoints between them bound it.
  void widen(double a, double b, Eigen::VectorXd& lo, Eigen::VectorXd& hi) const;
};

/// A device's commanded joint values over time: holds between segments.
struct Track {
  int object = -1;
  Eigen::VectorXd q_start;
  std::vector<Segment> segments;  ///< in time order, not overlapping
  Eigen::VectorXd at(double t) const;
  /// The box every joint value of [a, b] lies in (per joint, the least and the most).
  void range(double a, double b, Eigen::VectorXd& lo, Eigen::VectorXd& hi) const;
};

/// What a step does, in the order of kStepActionNames (and of a scenario step's alternatives).
enum class StepKind : uint8_t { MoveJoints, MoveTo, Grasp, Release, Wait, Parallel };
static_assert(std::size(kStepActionNames) == 6);
/// The step's key as the scenario writes it (`move_joints`, `grasp`, ...).
const char* step_kind_name(StepKind kind);

/// The default tool speed of a linear path (m/s): a `speed` in m/s is a fraction of it.
constexpr double kLinearSpeed = 0.25;

/// A scenario's step as planning takes it: names resolved to indices, values in SI
/// (pipeline/scenario.h compiles them from the file, where their mistakes are input errors).
/// A step whose device could not be resolved has device -1 and is skipped.
struct StepCommand {
  size_t index = 0;          ///< in the file's order; members of a parallel group have the group's
  StepKind kind = StepKind::Wait;
  SourceMark mark;
  int device = -1;
  double speed = 1;          ///< a fraction of the device's limits (linear: of kLinearSpeed)
  // move_joints
  bool home = false;                           ///< first every joint to its home value
  std::vector<std::pair<int, double>> joints;  ///< joint index -> value (SI, within limits)
  // move_to: a pose in the world, or an object's frame (where planning has the object then)
  std::optional<Eigen::Isometry3d> pose;
  int target = -1;
  std::string frame;
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
  bool linear = false;
  // grasp, release (object -1: what is held)
  int object = -1;
  std::string object_text;   ///< as written, for messages
  SourceMark object_mark;
  // wait
  double duration = 0;       ///< s
  // parallel
  std::vector<StepCommand> members;
};

/// A scenario compiled against its vault: settings and steps.
struct ScenarioCommands {
  SimSettings settings;
  std::vector<StepCommand> steps;
};

struct PlannedStep {
  size_t index = 0;           ///< in the file's order; members of a parallel group follow it
  StepKind kind = StepKind::Wait;
  SourceMark mark;
  int device = -1;
  int object = -1;            ///< grasp / release
  double start = 0, end = 0;
  int target = -1;            ///< move_to: the object whose frame the tool goes to (it may touch it)
  int job = -1;               ///< a campaign's job (Plan::jobs), or -1
};

/// A failure found while planning: `unreachable` or `singular`, at a step.
struct PlanFailure {
  double t = 0;
  EventKind kind = EventKind::Unreachable;  ///< Unreachable or Singular
  size_t step = 0;
  int device = -1;
  std::string message;
  double position_error = 0;  ///< unreachable: the best position error, m
  int job = -1;               ///< a campaign's job the step belongs to, or -1
};

/// A failure the run found that its plan did not (a grasp missed: the tool held back on what
/// was in the way): job `job` ends at its `step`-th step (0-based, in the template's order), at
/// `t`. A campaign going on after it (on_failure: continue) is planned again knowing it, so
/// that the device's queued jobs go to other devices (campaign-format.md, "Failure").
struct FoundInRun {
  size_t job = 0;
  size_t step = 0;
  double t = 0;
  std::string message;
};

/// One job of a campaign as dispatched: a template applied to an object, on a device, to a
/// place (a slot chosen, or the template's `to`), with its times as planned.
struct PlannedJob {
  std::string name;          ///< the template's
  int object = -1;
  int device = -1;           ///< -1: never started
  std::string place;         ///< `Row_1.top_3`, or ""
  double ready = 0, start = 0, end = 0;
  bool started = false;
  std::optional<size_t> failure;  ///< Plan::job_failures (or the plan's failure: SIZE_MAX)
  std::string why_not;       ///< never started: why (its devices out, no free slot, the limit)
};

struct Plan {
  SimSettings settings;
  std::vector<Track> tracks;          ///< one per device that moves or acts
  std::vector<PlannedStep> steps;     ///< in order of start
  std::optional<PlanFailure> failure; ///< planning stopped here
  /// The steps after the failure, never begun (times unset): the run's summary lists them too.
  std::vector<PlannedStep> not_begun;
  double end = 0;                     ///< when the last step ends (or the failure)
  /// A campaign's jobs as the dispatcher gave them out (PlannedStep::job indexes them).
  std::vector<PlannedJob> jobs;
  /// Failures that ended a job, not the run (a campaign going on after one: on_failure continue).
  std::vector<PlanFailure> job_failures;
  /// The frames a campaign's jobs choose slots from (every template's, once), where they are,
  /// and the object each is a frame of (which stands there: no load).
  struct SlotFrame {
    std::string name;
    Eigen::Vector3d position;
    int owner = -1;
  };
  std::vector<SlotFrame> slot_frames;
  std::vector<int> campaign_devices;  ///< every device a campaign's jobs may go to, in order
  /// A campaign's arriving loads: when each arrives (infinity: never, its spot stayed taken).
  std::vector<std::pair<int, double>> arrivals;
  /// A campaign with `on_failure: continue`: a job the run itself fails (a grasp missed) fails
  /// alone, its device out, and the run goes on. Otherwise such a failure stops the run.
  bool jobs_fail_alone = false;
  /// Such a campaign's failures found in earlier runs, which this plan knows (each job ends at
  /// its step, its device takes no more jobs), and how to plan it again knowing one more: the
  /// run stops at a failure it finds that is not here, and starts again on the new plan.
  std::vector<FoundInRun> found;
  std::function<std::optional<Plan>(const std::vector<FoundInRun>&)> replan;
  const FoundInRun* found_at(size_t job, size_t step) const {
    for (const FoundInRun& f : found)
      if (f.job == job && f.step == step) return &f;
    return nullptr;
  }
  /// A campaign with something due past `sim.limit` (a load, a job's `after`): it runs to the
  /// limit and fails there (campaign-format.md, "Time"), though nothing moves before.
  bool runs_to_limit = false;
  const Track* track(int object) const;
  /// Whether `ps` is the step the plan failed at (it began and never finished), or its group,
  /// or a step a job failed at.
  bool failed_at(const PlannedStep& ps) const {
    auto at = [&](const PlanFailure& f) { return ps.index == f.step && ps.end >= f.t - 1e-12; };
    if (failure && at(*failure)) return true;
    return std::any_of(job_failures.begin(), job_failures.end(), at);
  }
};

/// Plans a compiled scenario. Returns nullopt when an input error was reported (here or in `diag`
/// before: the steps that could not be compiled are skipped, and the others still checked).
std::optional<Plan> plan_scenario(const ScenarioCommands& scenario, const Workcell& wc, const GeometryModel& geometry,
                                  Diagnostics& diag);

}  // namespace sscs

namespace sscs {

/// Plans steps one at a time, each for its device no earlier than a given time (a campaign's
/// dispatcher, which decides what runs next from where planning has everything then).
class StepPlanner {
 public:
  StepPlanner(const SimSettings& settings, const Workcell& wc, const GeometryModel& geometry);
  ~StepPlanner();
  StepPlanner(const StepPlanner&) = delete;
  StepPlanner& operator=(const StepPlanner&) = delete;
  /// Plans `step` (of campaign job `job`) from t0, its input errors into `diag`; returns when it
  /// ends (at its failure when it failed: failure()).
  double plan(const StepCommand& step, double t0, int job, Diagnostics& diag);
  /// The failure of the last step planned, if it failed (then no other step is planned until
  /// it is taken).
  const std::optional<PlanFailure>& failure() const;
  /// Takes the failure away: a job ended by it, the plan goes on.
  PlanFailure take_failure();
  /// When `device`'s planned motions end.
  double free_at(int device);
  /// A campaign's load not yet arrived: planning leaves it out (what a move would meet, slots).
  void set_absent(int object, bool absent);
  /// World pose of object `o` where planning has it now, and of its frame `frame`.
  Eigen::Isometry3d object_pose(int o) const;
  Eigen::Isometry3d frame_pose(int o, const std::string& frame) const;
  /// The plan so far (jobs, steps not begun are added by the dispatcher).
  Plan& plan();
  /// The plan, steps in order of start; nullopt when an input error was reported (`diag`).
  std::optional<Plan> finish(Diagnostics& diag);

 private:
  std::unique_ptr<class Planner> planner_;
};

}  // namespace sscs
