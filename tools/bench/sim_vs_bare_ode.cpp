// sscs's simulation loop side by side with a bare ODE loop over the same world, on a scenario
// (default: the arm drum transfer, without frames). Three runs of the same number of steps:
//
//   sscs     run_simulation: motors, contacts, events, trajectory and object logs, clearances
//            and constraint re-checks at the trajectory rate (everything but writing files);
//   physics  sscs's PhysicsWorld alone: drive() and step() with grasps and releases on time,
//            no events and no logs;
//   bare     the same ODE bodies, joints and geoms (built by PhysicsWorld, not timed) stepped by
//            a plain loop: motor velocities set with dJointSetHingeParam from the plan plus the
//            same feedback, the same collision pass and callback, dWorldStep.
//
// Prints the time per step of each (best of N repetitions), sscs/bare, the share of the run
// spent on logging and event checks ((sscs - physics) / sscs), and the real-time factor
// (simulated seconds per wall second). Targets (issue 6): <= 1.5x, <= 10 %, >= 20x.
//
//   sim_vs_bare_ode [scenario=scenarios/drum-transfer/arm-loads-drum.yaml] [repetitions=5]
#include <ode/ode.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>

#include "pipeline/compile_vault.h"
#include "geometry/geometry.h"
#include "pipeline/scenario.h"
#include "simulate/plan.h"
#include "simulate/simulate.h"
#include "simulate/world.h"

namespace {

using Clock = std::chrono::steady_clock;
using namespace sscs;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// Grasps and releases due at step k (they are rare: two in the arm scenario).
void handle_steps(PhysicsWorld& world, const Plan& plan, double t, std::vector<char>& done) {
  const double dt = plan.settings.timestep;
  for (size_t i = 0; i < plan.steps.size(); ++i) {
    const PlannedStep& ps = plan.steps[i];
    if (done[i] || ps.start > t + dt / 2) continue;
    done[i] = 1;
    if (ps.kind == StepKind::Grasp) world.grasp(ps.device, ps.object);
    if (ps.kind == StepKind::Release && world.held(ps.device) >= 0) world.release(ps.device);
  }
}

/// Builds the run's world with its devices, then times `steps` steps of `advance(world, k, t)`
/// (grasps and releases handled on time around it).
template <typename Advance>
double timed_steps(const Workcell& wc, const GeometryModel& g, const Plan& plan, long steps, Advance advance) {
  PhysicsWorld world(wc, g, physics_options(plan.settings.timestep, plan.settings.gravity));
  for (const Track& t : plan.tracks) world.add_device(t.object, t.q_start);
  std::vector<char> done(plan.steps.size(), 0);
  const double dt = plan.settings.timestep;
  auto t0 = Clock::now();
  for (long k = 0; k < steps; ++k) {
    handle_steps(world, plan, k * dt, done);
    advance(world, k * dt);
  }
  return seconds_since(t0);
}

double physics_only(const Workcell& wc, const GeometryModel& g, const Plan& plan, long steps) {
  const double dt = plan.settings.timestep;
  return timed_steps(wc, g, plan, steps, [&](PhysicsWorld& world, double t) {
    for (const Track& tr : plan.tracks) {
      Eigen::VectorXd q1 = tr.at(t + dt);
      world.drive(tr.object, q1, (q1 - tr.at(t)) / dt);
    }
    world.step();
  });
}

double bare_ode(const Workcell& wc, const GeometryModel& g, const Plan& plan, long steps) {
  const double dt = plan.settings.timestep;
  std::vector<OdeHandles> handles;
  return timed_steps(wc, g, plan, steps, [&](PhysicsWorld& world, double t) {
    if (handles.empty())  // once, before the first step (not worth timing apart)
      for (const Track& tr : plan.tracks) handles.push_back(world.ode_handles(tr.object));
    for (size_t d = 0; d < plan.tracks.size(); ++d) {
      const Track& tr = plan.tracks[d];
      Eigen::VectorXd q1 = tr.at(t + dt), qd = (q1 - tr.at(t)) / dt;
      for (size_t j = 0; j < handles[d].motors.size(); ++j) {
        const OdeHandles::Motor& m = handles[d].motors[j];
        if (!m.joint) continue;
        double q = m.q_attach + (m.revolute ? dJointGetHingeAngle(m.joint) : dJointGetSliderPosition(m.joint));
        double v = qd[j] + 20 * (q1[j] - q);
        if (m.revolute) dJointSetHingeParam(m.joint, dParamVel, v);
        else dJointSetSliderParam(m.joint, dParamVel, v);
      }
    }
    const OdeHandles& ode = handles.at(0);
    ode.collide(ode.collide_data);
    dWorldStep(ode.world, dt);
    dJointGroupEmpty(ode.contact_group);
  });
}

}  // namespace

int main(int argc, char** argv) {
  std::string scenario = argc > 1 ? argv[1] : "scenarios/drum-transfer/arm-loads-drum.yaml";
  int reps = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  Sources sources;
  Diagnostics diag;
  auto spec = load_scenario(scenario, sources, diag);
  CompileOptions options;
  if (spec)
    for (const auto& [name, value] : spec->set) options.overrides.emplace_back(name, value.text);
  auto wc = spec && !diag.has_errors() ? compile_file(spec->vault_path, options, sources, diag) : std::nullopt;
  GeometryModel geometry;
  if (wc) geometry = build_geometry(*wc, diag);
  auto plan = wc && !diag.has_errors() ? plan_scenario(*spec, *wc, geometry, diag) : std::nullopt;
  if (diag.has_errors() || !plan) {
    std::fputs(diag.format(sources, false).c_str(), stderr);
    return 2;
  }
  double full = 1e9, phys = 1e9, bare = 1e9;
  double simulated = 0;
  long steps = 0;
  for (int r = 0; r < reps; ++r) {
    RunOptions run;  // no output folder: everything but writing the files
    auto t0 = Clock::now();
    Expected<RunSummary> s = run_simulation(*wc, geometry, *plan, run);
    full = std::min(full, seconds_since(t0));
    if (!s) {
      std::fprintf(stderr, "sim_vs_bare_ode: %s\n", s.error().c_str());
      return 1;
    }
    simulated = s->simulated;
    steps = std::lround(s->simulated / plan->settings.timestep);
  }
  for (int r = 0; r < reps; ++r) phys = std::min(phys, physics_only(*wc, geometry, *plan, steps));
  for (int r = 0; r < reps; ++r) bare = std::min(bare, bare_ode(*wc, geometry, *plan, steps));
  std::printf("%s: %ld steps of %g ms (%.3f s simulated), best of %d\n", scenario.c_str(), steps,
              plan->settings.timestep * 1e3, simulated, reps);
  std::printf("  %-8s %10s %12s\n", "", "wall (s)", "us / step");
  for (auto [name, t] : {std::pair{"sscs", full}, {"physics", phys}, {"bare", bare}})
    std::printf("  %-8s %10.4f %12.2f\n", name, t, t / steps * 1e6);
  std::printf("  sscs / bare time per step:      %.2fx   (target <= 1.5x)\n", full / bare);
  std::printf("  logging and event checks:       %.1f %%  (target <= 10 %%)\n", 100 * (full - phys) / full);
  std::printf("  real-time factor:               %.1fx   (target >= 20x)\n", simulated / full);
  return 0;
}
