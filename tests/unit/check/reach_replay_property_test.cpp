// Every solution `reach` accepts, replayed in the physics: the device placed at it touches
// nothing there either. ODE's collision detection is an oracle independent of the checker's (FCL
// with sscs's own mesh depths), so a pass the checker gives wrongly shows up as a contact.
#include <random>

#include <fmt/format.h>

#include "geometry/collision.h"
#include "model/device.h"
#include "pipeline/scenario.h"
#include "simulate/world.h"
#include "vault_fixture.h"

namespace sscs::testing {
namespace {

using ReachReplay = VaultTest;

/// How deep ODE may report a contact that is a touch: its box and mesh depths of bodies placed
/// face to face come out at a few micrometres.
constexpr double kOdeTouch = 1e-4;  // m

/// arm6 in the middle of a room (its j1, and j2 when `bent`, at random), four objects around it
/// at random distances (from `near`, `spread` further), turned at random: the vault's objects,
/// and their `top` frames as a reach target list. Primitive objects: reach among meshes costs
/// seconds a target (sscs's exact mesh depths, which MeshOverlap.* tests against their own oracle).
std::pair<std::string, std::string> random_scene(std::mt19937& rng, double near, double spread, bool bent) {
  std::uniform_real_distribution<double> unit(0, 1);
  const char* kinds[] = {"drum", "cart", "shelf"};
  const double j1 = -180 + 360 * unit(rng);
  std::string objects = fmt::format("  - {{type: room, name: Hall, length: 10, width: 10, height: 5}}\n"
                                    "  - {{type: arm6, name: R, parent: Hall, location: [5, 5, 0], j1: {:.3f}{}}}\n",
                                    j1, bent ? fmt::format(", j2: {:.3f}", -60 + 120 * unit(rng)) : "");
  std::string names;
  for (int k = 0; k < 4; ++k) {
    const double angle = 2 * std::numbers::pi * unit(rng), distance = near + spread * unit(rng);
    objects += fmt::format("  - {{type: {}, name: O{}, parent: Hall, location: [{:.3f}, {:.3f}, 0], orientation: [0, 0, {:.1f}]}}\n",
                           kinds[rng() % std::size(kinds)], k, 5 + distance * std::cos(angle), 5 + distance * std::sin(angle),
                           360 * unit(rng));
    names += fmt::format("{}O{}.top", k ? ", " : "", k);
  }
  return {objects, names};
}

TEST_F(ReachReplay, EverySolutionReachAcceptsIsFreeInThePhysics) {
  std::mt19937 rng(20261125);
  size_t solutions = 0, targets = 0;
  for (int scene = 0; scene < 40; ++scene) {
    SCOPED_TRACE(fmt::format("scene {}", scene));
    auto [objects, names] = random_scene(rng, 0.8, 0.8, false);
    Workcell wc = must_compile("objects:\n" + objects + "constraints:\n  - {name: reach, reach: {device: R, targets: [" + names + "]}}\n");
    GeometryModel geometry = build_geometry(wc, diag);
    ASSERT_FALSE(diag.has_errors()) << diag.format(sources);
    const int robot = wc.find_object("R");
    std::vector<std::pair<int, Eigen::VectorXd>> accepted;  // target object, joint values
    CheckOptions options;
    options.on_reach_solution = [&](int, int target, const Eigen::VectorXd& q) {
      accepted.emplace_back(wc.find_object(fmt::format("O{}", target)), q);
    };
    check(wc, geometry, options);
    targets += 4;
    const Device& d = *geometry.objects[robot].device;
    const std::vector<char> tool = d.tool_parts();
    for (const auto& [target, q] : accepted) {
      ++solutions;
      PhysicsWorld world(wc, geometry, PhysicsOptions{});
      world.add_device(robot, q);
      world.step();  // contacts are found at the placed poses, before the step integrates
      for (const PhysicsContact& c : world.contacts()) {
        if (c.a != robot && c.b != robot) continue;
        const bool self = c.a == c.b;
        const int other = self ? robot : c.a == robot ? c.b : c.a;
        const int part = c.a == robot ? c.part_a : c.part_b;
        const bool tool_on_target = !self && other == target && part >= 0 && tool[part];
        EXPECT_LE(c.depth, (tool_on_target ? kTargetTouch : 0) + kOdeTouch)
            << "reach accepted q = " << q.transpose() << " for O" << target - 2 << ".top, and ODE finds part "
            << d.parts[part].name << " in " << (other < 0 ? std::string("the floor") : self ? "R itself" : wc.objects[other].name)
            << " by " << c.depth << " m";
      }
    }
  }
  // The space was explored: tops in reach were reached (about one in five lies within 1.6 m).
  EXPECT_GE(solutions, 25u) << solutions << " solutions of " << targets << " targets";
}

TEST_F(ReachReplay, AMoveToEndsFreeWhereReachFoundAFreeSolution) {
  // The planner took the IK solution nearest the start, collisions unseen: an arm `check` passed
  // could end its move_to with the elbow in a neighbour where a free solution existed. Random
  // scenes as above; each target reach passes (tool pointing down at the top) is planned as a
  // move_to from the arm's start, and its end must be free as reach judges it.
  std::mt19937 rng(20261126);
  size_t planned = 0;
  for (int scene = 0; scene < 30; ++scene) {
    SCOPED_TRACE(fmt::format("scene {}", scene));
    auto [objects, names] = random_scene(rng, 0.7, 0.6, true);
    Workcell wc = must_compile("objects:\n" + objects + "constraints:\n  - {name: reach, reach: {device: R, targets: [" + names +
                               "], orientation: match, offset: {rpy: [180, 0, 0]}}}\n");
    GeometryModel geometry = build_geometry(wc, diag);
    ASSERT_FALSE(diag.has_errors()) << diag.format(sources);
    const int robot = wc.find_object("R");
    std::vector<int> reached;
    CheckOptions options;
    options.on_reach_solution = [&](int, int target, const Eigen::VectorXd&) { reached.push_back(target); };
    check(wc, geometry, options);
    const DeviceClearance clearance(wc, geometry, robot);
    for (int target : reached) {
      ++planned;
      const std::string steps = fmt::format("  - {{device: R, move_to: {{target: O{}.top, offset: {{rpy: [180, 0, 0]}}}}}}\n", target);
      uint32_t f = sources.add(fmt::format("s{}_{}.yaml", scene, target), "sscs: 1\nscenario: s\nvault: v.yaml\nsteps:\n" + steps);
      auto spec = load_scenario(f, sources, diag);
      ASSERT_TRUE(spec) << diag.format(sources);
      auto plan = plan_scenario(*spec, wc, geometry, diag);
      ASSERT_TRUE(plan && !plan->failure) << diag.format(sources);
      const Eigen::VectorXd q = plan->track(robot)->q_start.size() ? plan->track(robot)->at(plan->end) : Eigen::VectorXd();
      CollisionWorld world(geometry);
      auto hit = clearance.at(world, q, wc.find_object(fmt::format("O{}", target)), false);
      EXPECT_FALSE(hit) << "the move_to O" << target << ".top ends at q = " << q.transpose() << " with part "
                        << geometry.objects[robot].device->parts[hit->part].name << " in "
                        << (hit->other < 0 ? std::string("the floor or R") : wc.objects[hit->other].name) << " by " << hit->depth << " m";
    }
  }
  EXPECT_GE(planned, 15u);
}

}  // namespace
}  // namespace sscs::testing
