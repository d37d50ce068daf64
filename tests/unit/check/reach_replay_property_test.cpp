// Every solution `reach` accepts, replayed in the physics: the device placed at it touches
// nothing there either. ODE's collision detection is an oracle independent of the checker's (FCL
// with sscs's own mesh depths), so a pass the checker gives wrongly shows up as a contact.
#include <random>

#include <fmt/format.h>

#include "geometry/collision.h"
#include "model/device.h"
#include "simulate/world.h"
#include "vault_fixture.h"

namespace sscs::testing {
namespace {

using ReachReplay = VaultTest;

/// How deep ODE may report a contact that is a touch: its box and mesh depths of bodies placed
/// face to face come out at a few micrometres.
constexpr double kOdeTouch = 1e-4;  // m

TEST_F(ReachReplay, EverySolutionReachAcceptsIsFreeInThePhysics) {
  std::mt19937 rng(20261125);
  std::uniform_real_distribution<double> unit(0, 1);
  // Primitive objects: reach among meshes costs seconds a target (sscs's exact mesh depths, which
  // MeshOverlap.* tests against their own oracle).
  const char* kinds[] = {"drum", "cart", "shelf"};
  size_t solutions = 0, targets = 0;
  for (int scene = 0; scene < 40; ++scene) {
    SCOPED_TRACE(fmt::format("scene {}", scene));
    // arm6 in the middle of a room, four objects around it at random, each reached at its top.
    std::string objects = fmt::format("  - {{type: room, name: Hall, length: 10, width: 10, height: 5}}\n"
                                      "  - {{type: arm6, name: R, parent: Hall, location: [5, 5, 0], j1: {:.3f}}}\n",
                                      -180 + 360 * unit(rng));
    std::string names;
    for (int k = 0; k < 4; ++k) {
      const double angle = 2 * std::numbers::pi * unit(rng), distance = 0.8 + 0.8 * unit(rng);
      objects += fmt::format("  - {{type: {}, name: O{}, parent: Hall, location: [{:.3f}, {:.3f}, 0], orientation: [0, 0, {:.1f}]}}\n",
                             kinds[rng() % std::size(kinds)], k, 5 + distance * std::cos(angle), 5 + distance * std::sin(angle),
                             360 * unit(rng));
      names += fmt::format("{}O{}.top", k ? ", " : "", k);
    }
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

}  // namespace
}  // namespace sscs::testing
