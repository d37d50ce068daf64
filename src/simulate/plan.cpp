#include "simulate/plan.h"

#include "kinematics/closest.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>
#include <map>
#include <set>
#include <memory>

#include <fmt/format.h>

#include "core/inertia.h"
#include "core/names.h"
#include "core/pose.h"
#include "geometry/collision.h"
#include "kinematics/closest.h"
#include "kinematics/ik.h"
#include "simulate/world.h"
#include "core/units.h"

namespace sscs {

const char* step_kind_name(StepKind kind) { return kStepActionNames[static_cast<size_t>(kind)]; }
const char* sim_mode_name(SimMode m) { return m == SimMode::Fast ? "fast" : "physics"; }

namespace {

// Linear tool paths: default speeds and acceleration, waypoint spacing, and the largest joint
// step between waypoints that still counts as continuous (larger: a branch flip, a singularity).
constexpr double kLinearTurn = 45 * kPi / 180, kLinearAccel = 0.5;
constexpr double kSetDownGap = 0.05;        // m: an object released this close above a carried load's top is set on it
constexpr double kTargetTolerance = 1e-3;  // m: a move_to ends this close to its target, or fails
constexpr double kWaypointSpacing = 0.005, kWaypointTurn = kPi / 180;
constexpr double kContinuityRevolute = 5 * kPi / 180, kContinuityPrismatic = 0.05;

}  // namespace

class Planner {
  friend class StepPlanner;

 public:
  Planner(const Workcell& wc, const GeometryModel& geometry, Diagnostics& diag) : wc_(wc), geometry_(geometry), diag_(&diag) {}

  std::optional<Plan> run(const ScenarioCommands& scenario) {
    plan_.settings = scenario.settings;
    double t = 0;
    for (const StepCommand& step : scenario.steps) {
      if (plan_.failure) {
        not_begun(step);
        continue;
      }
      if (step.kind == StepKind::Parallel) {
        plan_.steps.push_back({step.index, StepKind::Parallel, step.mark, -1, -1, t, t});
        size_t group = plan_.steps.size() - 1;
        double end = t;
        for (const StepCommand& member : step.members) {
          if (plan_.failure) not_begun(member);
          else end = std::max(end, step_at(member, t));
        }
        plan_.steps[group].end = end;
        t = end;
      } else {
        t = step_at(step, t);
      }
      if (diag_->full()) break;
    }
    plan_.end = plan_.failure ? plan_.failure->t : t;
    carried_devices();
    if (diag_->has_errors()) return std::nullopt;
    return std::move(plan_);
  }

 private:
  struct DeviceState {
    size_t track = 0;
    Eigen::VectorXd q;   ///< commanded at `free`
    double free = 0;     ///< when its last planned motion ends
    int held = -1;
    Eigen::Isometry3d X_tool_held = Eigen::Isometry3d::Identity();
  };

  const Device& model(int d) const { return *geometry_.objects[d].device; }

  /// A device standing on another (an arm whose parent is an AGV) is not carried when that one
  /// moves: it stayed where it was, in the air. An input error at the carrier's first motion.
  void carried_devices() {
    for (const PlannedStep& ps : plan_.steps) {
      if (ps.device < 0 || (ps.kind != StepKind::MoveTo && ps.kind != StepKind::MoveJoints)) continue;
      for (size_t k = 0; k < wc_.objects.size(); ++k) {
        if (!geometry_.objects[k].device || static_cast<int>(k) == ps.device) continue;
        for (int up = wc_.objects[k].parent; up >= 0; up = wc_.objects[up].parent)
          if (up == ps.device) {
            diag_->error(ps.mark, fmt::format("{} stands on {}, which this step moves: sscs does not carry one device on another "
                                             "(make them one device type, the arm's joints after the vehicle's)",
                                             wc_.objects[k].name, wc_.objects[ps.device].name));
            return;
          }
      }
    }
  }

  DeviceState& state(int d) {
    auto it = states_.find(d);
    if (it != states_.end()) return it->second;
    const Device& m = model(d);
    DeviceState st;
    st.q = m.joint_values(&wc_.values[wc_.objects[d].first_slot + kFirstAttributeSlot]);
    st.track = plan_.tracks.size();
    plan_.tracks.push_back({d, st.q, {}});
    return states_.emplace(d, std::move(st)).first->second;
  }

  /// An object's bounds in its own frame.
  Eigen::AlignedBox3d local_bounds(int o) const {
    Eigen::AlignedBox3d box;
    for (const Shape& sh : geometry_.objects[o].shapes) box.extend(shape_bounds(sh, sh.X_object_shape));
    return box;
  }

  /// Object o, released by device d at X, set down on a load another device holds (or on what
  /// rides on one): it moves with that load from then on (a drum set on the pallet a forklift
  /// held stayed, for planning, where it was released, and the arm later went 0.3 m off it).
  void set_down_on(int o, const Eigen::Isometry3d& X, int d) {
    set_on_.erase(o);
    const Eigen::AlignedBox3d mine = local_bounds(o);
    if (mine.isEmpty()) return;
    const Eigen::Vector3d bottom_middle = X * Eigen::Vector3d(mine.center().x(), mine.center().y(), mine.min().z());
    for (const auto& [dev, other] : states_) {
      if (dev == d) continue;
      std::vector<int> loads;
      if (other.held >= 0) loads.push_back(other.held);
      for (const auto& [rider, on] : set_on_)
        if (on.first == other.held) loads.push_back(rider);
      for (int load : loads) {
        const Eigen::AlignedBox3d box = local_bounds(load);
        if (box.isEmpty()) continue;
        const Eigen::Isometry3d X_load = object_pose(load);
        const Eigen::Vector3d p = X_load.inverse() * bottom_middle;  // in the load's frame
        const bool over = p.x() >= box.min().x() && p.x() <= box.max().x() && p.y() >= box.min().y() && p.y() <= box.max().y();
        if (over && p.z() >= box.max().z() - kSetDownGap && p.z() <= box.max().z() + kSetDownGap) {
          set_on_[o] = {load, X_load.inverse() * X};
          return;
        }
      }
    }
  }

  /// Whether object o is `load` or moves with it: set down on it, or standing on it (its parent
  /// chain), as object_pose places it.
  bool moves_with(int o, int load) const {
    for (int at = o; at >= 0;) {
      if (at == load) return true;
      if (auto on = set_on_.find(at); on != set_on_.end()) {
        at = on->second.first;
      } else {
        const int up = wc_.objects[at].parent;
        if (moved_.count(at) || (up >= 0 && wc_.types[wc_.objects[up].type].container)) return false;
        at = up;
      }
    }
    return false;
  }

  /// What device d's tool holds now, and what rides on it, at their poses in the tool's frame:
  /// a move_to's joint values are chosen free of collision for these too (of two solutions for
  /// one tool pose, not the one whose forearm the held drum goes into; and a target where the
  /// load itself would be in something has no free solution, so the nearest is taken and the
  /// run shows the collision).
  HeldLoad held_load(int d, const DeviceState& st) const {
    HeldLoad load;
    if (st.held < 0) return load;
    const Eigen::Isometry3d X_tool_world = tool_world(d, st.q).inverse();
    for (size_t o = 0; o < wc_.objects.size(); ++o)
      if (!geometry_.objects[o].device && moves_with(static_cast<int>(o), st.held))
        load.objects.emplace_back(static_cast<int>(o), X_tool_world * object_pose(static_cast<int>(o)));
    return load;
  }

  /// World pose of an object now: where planning last put it (carried, placed), else where
  /// its parent's move took it (a drum on a pallet a forklift carried: the arm went to where
  /// the drum stood in the vault, 1 m from it), else its pose. What the physics then does (a
  /// drum falls, rolls) is checked when the run grasps (grasp_missed).
  Eigen::Isometry3d object_pose(int o) const {
    for (const auto& [d, st] : states_)
      if (st.held == o) return tool_world(d, st.q) * st.X_tool_held;
    if (auto on = set_on_.find(o); on != set_on_.end()) return object_pose(on->second.first) * on->second.second;
    if (auto it = moved_.find(o); it != moved_.end()) return it->second;
    const Eigen::Isometry3d& X = geometry_.objects[o].X_world_object;
    if (const int up = wc_.objects[o].parent; up >= 0 && !wc_.types[wc_.objects[up].type].container)
      return object_pose(up) * geometry_.objects[up].X_world_object.inverse() * X;
    return X;
  }

  Eigen::Isometry3d tool_world(int d, const Eigen::VectorXd& q) const {
    return geometry_.objects[d].X_world_object * model(d).tool_pose(q);
  }

  /// A step after the failure: listed, never begun (a group with its members).
  void not_begun(const StepCommand& step) {
    PlannedStep ps{step.index, step.kind, step.mark, step.device, step.object, 0, 0};
    plan_.not_begun.push_back(ps);
    for (const StepCommand& member : step.members) not_begun(member);
  }

  void fail(double t, EventKind kind, size_t step, int d, std::string message, double error = 0) {
    plan_.failure = PlanFailure{t, kind, step, d, std::move(message), error, job_};
  }

  /// Plans one step starting at t0; returns when it ends.
  double step_at(const StepCommand& step, double t0) {
    const size_t index = step.index;
    PlannedStep ps{index, step.kind, step.mark, -1, -1, t0, t0};
    ps.job = job_;
    if (step.kind == StepKind::Wait) {
      ps.end = t0 + step.duration;
      plan_.steps.push_back(ps);
      return ps.end;
    }
    const int d = step.device;
    if (d < 0) return t0;
    ps.device = d;
    DeviceState& st = state(d);
    const Device& m = model(d);
    double start = std::max(t0, st.free);
    ps.start = start;
    double end = start;
    if (step.kind == StepKind::MoveJoints) {
      Eigen::VectorXd target = st.q;
      const ObjectType& type = wc_.types[wc_.objects[d].type];
      if (step.home)
        for (int k = 0; k < m.dof(); ++k) target[k] = type.attributes[m.joint(k).attribute].home_si;
      for (const auto& [k, value] : step.joints) target[k] = value;
      end = move_joints(st, m, target, step.speed, start);
    } else if (step.kind == StepKind::MoveTo) {
      ps.target = step.target;
      Eigen::Isometry3d target = step.pose ? *step.pose : frame_now(step.target, step.frame);
      Eigen::Isometry3d X = target * step.offset;
      if (step.linear) end = move_linear(st, d, X, step.speed, index, start);
      else end = move_to_joint(st, d, X, ps.target, step.speed, index, start);
    } else if (step.kind == StepKind::Grasp) {
      ps.object = step.object;
      if (step.object >= 0) grasp(st, d, step.object, step);
    } else if (step.kind == StepKind::Release) {
      const int o = step.object >= 0 ? step.object : st.held;
      ps.object = o;
      if (st.held < 0) {
        diag_->error(step.mark, fmt::format("release: {} holds nothing at this step", wc_.objects[d].name));
      } else if (o != st.held) {
        diag_->error(step.object_mark, fmt::format("release: {} holds {}, not {}", wc_.objects[d].name, wc_.objects[st.held].name,
                                                  step.object_text));
      } else {
        const Eigen::Isometry3d X = tool_world(d, st.q) * st.X_tool_held;
        moved_[st.held] = X;
        set_down_on(st.held, X, d);
        st.held = -1;
      }
    }
    ps.end = plan_.failure ? plan_.failure->t : end;
    st.free = ps.end;
    plan_.steps.push_back(ps);
    return ps.end;
  }

  double move_joints(DeviceState& st, const Device& m, const Eigen::VectorXd& target, double f, double start) {
    Eigen::VectorXd v(m.dof()), a(m.dof());
    for (int k = 0; k < m.dof(); ++k) {
      v[k] = m.joint(k).max_speed() * f;
      a[k] = m.joint(k).max_acceleration() * f * f;  // the same motion, slower in time: twice the time at 50 %
    }
    Segment seg;
    seg.joint.emplace(st.q, target, v, a);
    seg.t0 = start;
    seg.t1 = start + seg.joint->duration();
    seg.q_end = target;
    plan_.tracks[st.track].segments.push_back(std::move(seg));
    st.q = target;
    return plan_.tracks[st.track].segments.back().t1;
  }

  /// An object's frame where planning has the object now (carried, set down, or where it stood).
  Eigen::Isometry3d frame_now(int o, const std::string& frame) const {
    const ObjectGeometry& g = geometry_.objects[o];
    return object_pose(o) * (g.X_world_object.inverse() * g.frame_pose(frame));
  }

  IkOptions ik_options() const {
    IkOptions opt;
    opt.position_tol = 1e-5;
    opt.angle_tol = 1e-4;
    opt.time_limit = INFINITY;  // no clock: the iteration budget ends a solve, the same on any machine
    return opt;
  }

  /// A target the solver did not reach: the closest the device comes to it over its whole joint
  /// range (kinematics/closest.h), as `reach` measures it, into `r`. True when that reaches it
  /// after all (r then holds the solution).
  bool closest_instead(const Chain& chain, const Eigen::Isometry3d& target, IkResult& r) const {
    const IkOptions opt = ik_options();
    const ClosestReach c = closest_reach(chain, target, opt.orientation, r.q);
    if (!c.found) return false;
    r.q = c.q;
    r.position_error = c.position_error;
    r.angle_error = c.angle_error;
    if (c.position_error > opt.position_tol || c.angle_error > opt.angle_tol) return false;
    r.status = IkResult::Status::Reached;
    return true;
  }

  std::string unreachable_message(int d, const IkResult& r) const {
    return fmt::format("{} cannot reach the move_to target: the closest its tool comes is {:g} m{}", wc_.objects[d].name,
                       stable(r.position_error), r.angle_error > 1e-9 ? fmt::format(" (turned {:g} deg off)", stable(r.angle_error * 180 / kPi)) : "");
  }

  /// The guard behind the solver: the joint values a move ends at put the tool on its target
  /// (a solver that returned shifted values once sent a crane to 5.7 m instead of 12 m, and the
  /// run said ok). A miss beyond 1 mm fails the plan; it never runs silently elsewhere.
  bool ends_at_target(const Chain& chain, const Eigen::VectorXd& q, const Eigen::Isometry3d& target, size_t index, int d,
                      double start) {
    double miss = (chain.forward(q).translation() - target.translation()).norm();
    if (std::isfinite(miss) && miss <= kTargetTolerance) return true;
    fail(start, EventKind::Unreachable, index, d,
         fmt::format("{}: the solved joint values put the tool {:g} m from the move_to target", wc_.objects[d].name, stable(miss)), miss);
    return false;
  }

  /// The collision world as planning has the scene now: loads where they are carried or were
  /// set down, the other devices at their last planned joint values.
  CollisionWorld& scene_now() {
    if (!collisions_) collisions_ = std::make_unique<CollisionWorld>(geometry_);
    for (size_t o = 0; o < wc_.objects.size(); ++o) {  // what was carried, set down, or stood on that
      if (geometry_.objects[o].device) continue;
      const Eigen::Isometry3d X = absent_.count(static_cast<int>(o)) ? absent_pose(static_cast<int>(o)) : object_pose(static_cast<int>(o));
      if (placed_.count(static_cast<int>(o)) || !X.isApprox(geometry_.objects[o].X_world_object, 1e-12)) {
        collisions_->move(static_cast<int>(o), X);
        placed_.insert(static_cast<int>(o));
      }
    }
    for (const auto& [dev, s] : states_) {
      std::vector<Eigen::Isometry3d> X = model(dev).part_poses(s.q);
      for (auto& x : X) x = geometry_.objects[dev].X_world_object * x;
      collisions_->move_parts(dev, X);
    }
    return *collisions_;
  }

  /// A joint-space move_to ends at joint values that are free as `reach` judges them
  /// (DeviceClearance, against the scene as planned so far) when the solver finds such: the
  /// solution nearest the start was taken before, and an arm `check` passed collided in the run
  /// where a free solution existed. With none free, the nearest (the run shows its collision).
  /// The path to it is not planned around obstacles.
  double move_to_joint(DeviceState& st, int d, const Eigen::Isometry3d& X_world, int target_object, double f, size_t index,
                       double start) {
    const Device& m = model(d);
    Chain chain(m);
    Eigen::Isometry3d target = geometry_.objects[d].X_world_object.inverse() * X_world;
    auto [it, fresh] = clearances_.try_emplace(d, wc_, geometry_, d);
    const DeviceClearance& clearance = it->second;
    CollisionWorld& scene = scene_now();
    const HeldLoad load = held_load(d, st);
    auto free = [&](const Eigen::VectorXd& chain_q) {
      Eigen::VectorXd q = st.q;
      chain.to_device(chain_q, q);
      return !clearance.at(scene, q, target_object, true, {}, load);
    };
    IkResult r = solve_ik(chain, target, chain.from_device(st.q), ik_options(), free);
    if (r.status == IkResult::Status::Rejected) r = solve_ik(chain, target, chain.from_device(st.q), ik_options());
    if (!r.ok() && !closest_instead(chain, target, r)) {
      fail(start, EventKind::Unreachable, index, d, unreachable_message(d, r), r.position_error);
      return start;
    }
    if (!ends_at_target(chain, r.q, target, index, d, start)) return start;
    Eigen::VectorXd q = st.q;
    chain.to_device(r.q, q);
    return move_joints(st, m, q, f, start);
  }

  double move_linear(DeviceState& st, int d, const Eigen::Isometry3d& X_world, double f, size_t index,
                     double start) {
    const Device& m = model(d);
    Chain chain(m);
    const Eigen::Isometry3d X_root = geometry_.objects[d].X_world_object.inverse();
    Eigen::Isometry3d T0 = chain.forward(chain.from_device(st.q)), T1 = X_root * X_world;
    // The end must be reachable at all, else the failure is "unreachable", not a path problem.
    IkResult end_ik = solve_ik(chain, T1, chain.from_device(st.q), ik_options());
    if (!end_ik.ok() && !closest_instead(chain, T1, end_ik)) {
      fail(start, EventKind::Unreachable, index, d, unreachable_message(d, end_ik), end_ik.position_error);
      return start;
    }
    if (!ends_at_target(chain, end_ik.q, T1, index, d, start)) return start;
    double length = (T1.translation() - T0.translation()).norm();
    Eigen::Quaterniond r0(T0.linear()), r1(T1.linear());
    double turn = r0.angularDistance(r1);
    int n = std::clamp(static_cast<int>(std::ceil(std::max(length / kWaypointSpacing, turn / kWaypointTurn))), 1, 5000);
    Segment seg;
    seg.t0 = start;
    Eigen::VectorXd q = chain.from_device(st.q);
    seg.waypoints.emplace_back(0.0, st.q);
    IkOptions local = ik_options();
    local.max_attempts = 1;  // continuation from the previous waypoint only: a restart could flip branches
    local.iterations_per_attempt = 100;
    double max_rate = 0;  // largest |dq/ds| relative to each joint's speed, and to its acceleration
    double max_rate_a = 0;
    for (int i = 1; i <= n; ++i) {
      double s = static_cast<double>(i) / n;
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = T0.translation() + s * (T1.translation() - T0.translation());
      T.linear() = r0.slerp(s, r1).toRotationMatrix();
      IkResult r = solve_ik(chain, T, q, local);
      bool jump = false;
      for (int k = 0; r.ok() && k < chain.size(); ++k) {
        double step_k = std::abs(r.q[k] - q[k]);
        const Joint& j = m.joint(chain.device_index(k));
        if (step_k > (j.type == JointType::Revolute ? kContinuityRevolute : kContinuityPrismatic)) jump = true;
        max_rate = std::max(max_rate, step_k * n / j.max_speed());
        max_rate_a = std::max(max_rate_a, step_k * n / j.max_acceleration());
      }
      if (!r.ok() || jump) {
        fail(start, EventKind::Singular, index, d,
             fmt::format("{} cannot follow the straight line: {} at {:g} % of the path (a singularity, a joint limit "
                         "or a change of arm configuration)", wc_.objects[d].name, jump ? "the joints jump" : "no continuous solution",
                         stable(100 * s)));
        return start;
      }
      q = r.q;
      Eigen::VectorXd full = st.q;
      chain.to_device(q, full);
      seg.waypoints.emplace_back(s, full);
    }
    // Time scaling along s: the tool's speed (from `speed` or the default), and every joint
    // within its speed and acceleration limits (the path's curvature term is neglected).
    double vs = INFINITY, as = INFINITY;
    if (length > 0) {
      vs = std::min(vs, kLinearSpeed * f / length);
      as = std::min(as, kLinearAccel / length);
    }
    if (turn > 0) vs = std::min(vs, kLinearTurn * f / turn);
    if (max_rate > 0) vs = std::min(vs, 1.0 / max_rate);
    if (max_rate_a > 0) as = std::min(as, 1.0 / max_rate_a);
    if (!std::isfinite(vs)) vs = 1;
    if (!std::isfinite(as)) as = 1;
    seg.timing = fastest(1.0, vs, as);
    seg.t1 = start + seg.timing.duration();
    seg.q_end = seg.waypoints.back().second;
    st.q = seg.q_end;
    plan_.tracks[st.track].segments.push_back(std::move(seg));
    return plan_.tracks[st.track].segments.back().t1;
  }

  void grasp(DeviceState& st, int d, int o, const StepCommand& where) {
    if (st.held >= 0) {
      diag_->error(where.object_mark, fmt::format("grasp: {} already holds {}", wc_.objects[d].name, wc_.objects[st.held].name));
      return;
    }
    for (const auto& [other, s] : states_)
      if (s.held == o) {
        diag_->error(where.object_mark, fmt::format("grasp: {} is held by {}", where.object_text, wc_.objects[other].name));
        return;
      }
    if (o == d || geometry_.objects[o].bbox_world.isEmpty()) {
      diag_->error(where.object_mark, fmt::format("grasp: {} cannot be grasped (it is the device itself or has no geometry)", where.object_text));
      return;
    }
    if (wc_.types[wc_.objects[o].type].container) {
      diag_->error(where.object_mark, fmt::format("grasp: {} is a container (a space that holds objects, such as a room): nothing lifts it",
                                          where.object_text));
      st.held = o;  // as if held: its release is no second error
      return;
    }
    if (wc_.types[wc_.objects[o].type].zone) {
      diag_->error(where.object_mark, fmt::format("grasp: {} is a keep-out zone (a volume devices must not enter): nothing lifts it",
                                          where.object_text));
      st.held = o;
      return;
    }
    // A body the physics cannot integrate (ODE aborts, or loses every digit) is no run.
    if (const double m = object_mass(wc_, geometry_, o); !simulable_mass(m)) {
      diag_->error(where.object_mark, fmt::format("grasp: {} has a mass of {:g} kg, beyond the 1e-6 to 1e7 kg the physics integrates",
                                          where.object_text, m));
      st.held = o;  // as if held: its release is no second error
      return;
    }
    // A device standing on the object would not be carried (as on a moving device).
    for (size_t k = 0; k < wc_.objects.size(); ++k)
      if (geometry_.objects[k].device)
        for (int up = wc_.objects[k].parent; up >= 0; up = wc_.objects[up].parent)
          if (up == o) {
            diag_->error(where.object_mark, fmt::format("grasp: {} stands on {} (its parent chain), and a device is not carried by what "
                                                "it stands on; place it elsewhere", wc_.objects[k].name, where.object_text));
            return;
          }
    // The tool must be at the object: within kGraspReach of its solids where it is now (its
    // bounds let a tool 0.2 m from a plank turned 45 deg grasp it).
    Eigen::Isometry3d X_tool = tool_world(d, st.q);
    CollisionWorld& scene = scene_now();
    double gap = scene.distance_to_point(o, X_tool.translation()).value_or(INFINITY);
    if (gap > kGraspReach) {
      diag_->error(where.object_mark, fmt::format("grasp: the tool of {} is {:g} m from {} (at most {:g} m); move it there first",
                                          wc_.objects[d].name, stable(gap), where.object_text, kGraspReach));
      return;
    }
    st.X_tool_held = X_tool.inverse() * object_pose(o);  // before it is held: object_pose follows the tool then
    st.held = o;
  }

  const Workcell& wc_;
  const GeometryModel& geometry_;
  Diagnostics* diag_;
  int job_ = -1;  // the campaign job whose steps are planned, or -1
  std::set<int> absent_;  // a campaign's loads not arrived yet
  Plan plan_;
  std::map<int, DeviceState> states_;
  std::map<int, Eigen::Isometry3d> moved_;
  std::map<int, std::pair<int, Eigen::Isometry3d>> set_on_;  // set down on a carried load: that load, its pose on it
  std::unique_ptr<CollisionWorld> collisions_;    // built at the first move_to or grasp
  std::set<int> placed_;                          // objects collisions_ has moved from their vault pose
  std::map<int, DeviceClearance> clearances_;     // per device moved to a target
};


Eigen::VectorXd Segment::at(double t) const {
  if (joint) return joint->position(t - t0);
  if (waypoints.empty()) return q_end;
  double s = std::clamp(timing.position(t - t0), 0.0, 1.0);
  auto it = std::lower_bound(waypoints.begin(), waypoints.end(), s, [](const auto& w, double x) { return w.first < x; });
  if (it == waypoints.begin()) return it->second;
  if (it == waypoints.end()) return waypoints.back().second;
  auto prev = it - 1;
  double u = (s - prev->first) / (it->first - prev->first);
  return prev->second + u * (it->second - prev->second);
}

void Segment::widen(double a, double b, Eigen::VectorXd& lo, Eigen::VectorXd& hi) const {
  a = std::max(a, t0);
  b = std::min(b, t1);
  if (a > b) return;
  auto take = [&](const Eigen::VectorXd& q) {
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  };
  take(at(a));
  take(at(b));
  if (joint || waypoints.empty()) return;
  const double s_a = std::clamp(timing.position(a - t0), 0.0, 1.0), s_b = std::clamp(timing.position(b - t0), 0.0, 1.0);
  for (const auto& [s, q] : waypoints)
    if (s > std::min(s_a, s_b) && s < std::max(s_a, s_b)) take(q);
}

void Track::range(double a, double b, Eigen::VectorXd& lo, Eigen::VectorXd& hi) const {
  lo = hi = at(a);
  const Eigen::VectorXd q_b = at(b);
  lo = lo.cwiseMin(q_b);
  hi = hi.cwiseMax(q_b);
  // Between segments it holds where the last one ended: at(a) or a segment's end covers it.
  for (const Segment& s : segments) {
    if (s.t1 < a) continue;
    if (s.t0 > b) break;
    s.widen(a, b, lo, hi);
  }
}

Eigen::VectorXd Track::at(double t) const {
  Eigen::VectorXd q = q_start;
  for (const Segment& s : segments) {
    if (t < s.t0) break;
    if (t <= s.t1) return s.at(t);
    q = s.q_end;
  }
  return q;
}

const Track* Plan::track(int object) const {
  for (const Track& t : tracks)
    if (t.object == object) return &t;
  return nullptr;
}

std::optional<Plan> plan_scenario(const ScenarioCommands& scenario, const Workcell& wc, const GeometryModel& geometry,
                                  Diagnostics& diag) {
  return Planner(wc, geometry, diag).run(scenario);
}

namespace {
Diagnostics& unused_diagnostics() {
  thread_local Diagnostics none;
  return none;
}
}  // namespace

StepPlanner::StepPlanner(const SimSettings& settings, const Workcell& wc, const GeometryModel& geometry)
    : planner_(std::make_unique<Planner>(wc, geometry, unused_diagnostics())) {
  planner_->plan_.settings = settings;
}

StepPlanner::~StepPlanner() = default;

double StepPlanner::plan(const StepCommand& step, double t0, int job, Diagnostics& diag) {
  planner_->diag_ = &diag;
  planner_->job_ = job;
  const double end = planner_->step_at(step, t0);
  planner_->diag_ = &unused_diagnostics();
  return end;
}

const std::optional<PlanFailure>& StepPlanner::failure() const { return planner_->plan_.failure; }

PlanFailure StepPlanner::take_failure() {
  PlanFailure f = *planner_->plan_.failure;
  planner_->plan_.failure.reset();
  return f;
}

double StepPlanner::free_at(int device) { return planner_->state(device).free; }

void StepPlanner::set_absent(int object, bool absent) {
  if (absent) planner_->absent_.insert(object);
  else planner_->absent_.erase(object);
}


Eigen::Isometry3d StepPlanner::object_pose(int o) const { return planner_->object_pose(o); }

Eigen::Isometry3d StepPlanner::frame_pose(int o, const std::string& frame) const { return planner_->frame_now(o, frame); }

Plan& StepPlanner::plan() { return planner_->plan_; }

std::optional<Plan> StepPlanner::finish(Diagnostics& diag) {
  Plan& p = planner_->plan_;
  // The run starts and ends steps in order of start (jobs on several devices interleave).
  std::stable_sort(p.steps.begin(), p.steps.end(), [](const PlannedStep& a, const PlannedStep& b) { return a.start < b.start; });
  p.end = 0;
  for (const PlannedStep& ps : p.steps) p.end = std::max(p.end, ps.end);
  if (p.failure) p.end = p.failure->t;
  planner_->diag_ = &diag;
  planner_->carried_devices();
  planner_->diag_ = &unused_diagnostics();
  if (diag.has_errors()) return std::nullopt;
  return std::move(p);
}

}  // namespace sscs
