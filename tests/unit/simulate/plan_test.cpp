#include <cmath>
#include <numbers>
#include <random>

#include <fmt/format.h>

#include "geometry/geometry.h"
#include "model/device.h"
#include "kinematics/ik.h"
#include "pipeline/scenario.h"
#include "vault_fixture.h"
#include "core/units.h"

namespace sscs::testing {
namespace {


// A turntable: one revolute joint at 90 deg/s and 180 deg/s^2, its tool 1 m out along x.
const char* kTurntable = R"(sscs: 1
type: turntable
kind: device
parts:
  - {name: base, geometry: [{cylinder: {radius: 0.2, length: 0.1, xyz: [0, 0, 0.05]}}]}
  - name: arm
    parent: base
    joint: {name: a, type: revolute, axis: [0, 0, 1], xyz: [0, 0, 0.1], limits: {min: -170, max: 170, velocity: 90, acceleration: 180}}
    geometry: [{box: {size: [1, 0.1, 0.05], xyz: [0.5, 0, 0]}}]
tool: {part: arm, xyz: [1, 0, 0]}
)";

class Planning : public VaultTest {
 public:
  std::optional<Plan> plan(const std::string& objects, const std::string& steps, const std::string& lib = "") {
    if (!lib.empty()) options.library_dirs = {lib};
    wc_ = must_compile("objects:\n" + objects);
    geometry_ = build_geometry(wc_, diag);
    uint32_t f = sources.add("s.yaml", "sscs: 1\nscenario: s\nvault: v.yaml\nsteps:\n" + steps);
    auto spec = load_scenario(f, sources, diag);
    EXPECT_TRUE(spec);
    if (!spec || diag.has_errors()) return std::nullopt;
    return plan_scenario(*spec, wc_, geometry_, diag);
  }
  Eigen::Isometry3d tool(const Plan& p, const std::string& device, double t) {
    int o = wc_.find_object(device);
    return geometry_.objects[o].X_world_object * geometry_.objects[o].device->tool_pose(p.track(o)->at(t));
  }
  /// A vault of one standard device `kind` named D (diagnostics cleared): the device.
  const Device& only_device(const std::string& kind) {
    diag = Diagnostics{};
    wc_ = must_compile(fmt::format("objects:\n  - {{type: {}, name: D}}\n", kind));
    geometry_ = build_geometry(wc_, diag);
    return *geometry_.objects[0].device;
  }
  /// A move_to step of D to the world pose X (`extra`: more of its keys).
  static std::string move_to_step(const Eigen::Isometry3d& X, const std::string& extra = "") {
    const Eigen::Vector3d rpy = X.linear().eulerAngles(2, 1, 0).reverse() / kRadPerDeg;
    return fmt::format("  - {{device: D, move_to: {{target: {{xyz: [{:.17g}, {:.17g}, {:.17g}], rpy: [{:.17g}, {:.17g}, {:.17g}]}}}}{}}}\n",
                       X.translation().x(), X.translation().y(), X.translation().z(), rpy.x(), rpy.y(), rpy.z(), extra);
  }
  /// The plan of `steps` in the vault compiled last.
  std::optional<Plan> plan_steps(const std::string& steps) {
    uint32_t f = sources.add("s.yaml", "sscs: 1\nscenario: s\nvault: v.yaml\nsteps:\n" + steps);
    auto spec = load_scenario(f, sources, diag);
    EXPECT_TRUE(spec) << diag.format(sources);
    if (!spec) return std::nullopt;
    return plan_scenario(*spec, wc_, geometry_, diag);
  }
  Workcell wc_;
  GeometryModel geometry_;
};

TEST_F(Planning, ASingleJointMoveTakesTheTrapezoidTime) {
  auto p = plan("  - {type: turntable, name: T}\n", "  - {device: T, move_joints: {a: 90}}\n  - wait: 0.5 s\n",
                type_dir({{"turntable", kTurntable}}));
  ASSERT_TRUE(p) << diag.format(sources);
  ASSERT_EQ(p->steps.size(), 2u);
  EXPECT_NEAR(p->steps[0].end, 1.5, 1e-12);  // 90 deg at 90 deg/s and 180 deg/s^2
  EXPECT_NEAR(p->steps[1].end, 2.0, 1e-12);
  EXPECT_NEAR(p->end, 2.0, 1e-12);
  EXPECT_NEAR(p->track(0)->at(0.75)[0], 45 * kRadPerDeg, 1e-12);
  EXPECT_NEAR(p->track(0)->at(9)[0], 90 * kRadPerDeg, 1e-12);
}

TEST_F(Planning, ACoarseTimestepIsWarnedOf) {
  // Above 10 ms a run can report collisions and tracking errors the design does not have.
  options.library_dirs = {type_dir({{"turntable", kTurntable}})};
  wc_ = must_compile("objects:\n  - {type: turntable, name: T}\n");
  geometry_ = build_geometry(wc_, diag);
  for (const auto& [timestep, warned] : {std::pair{"10 ms", false}, std::pair{"20 ms", true}}) {
    diag = Diagnostics();
    uint32_t f = sources.add(fmt::format("s{}.yaml", timestep), fmt::format("sscs: 1\nscenario: s\nvault: v.yaml\nsim: {{timestep: {}}}\n"
                                                                         "steps:\n  - {{device: T, move_joints: {{a: 90}}}}\n", timestep));
    auto spec = load_scenario(f, sources, diag);
    ASSERT_TRUE(spec);
    ASSERT_TRUE(plan_scenario(*spec, wc_, geometry_, diag)) << diag.format(sources);
    ASSERT_EQ(diag.warnings().size(), warned ? 1u : 0u) << timestep;
    if (warned) {
      EXPECT_NE(diag.warnings()[0].message.find("sim.timestep 20 ms is coarse"), std::string::npos) << diag.warnings()[0].message;
    }
  }
}

TEST_F(Planning, SpeedScalesTheLimits) {
  auto p = plan("  - {type: turntable, name: T}\n", "  - {device: T, move_joints: {a: 90}, speed: 50%}\n",
                type_dir({{"turntable", kTurntable}}));
  ASSERT_TRUE(p) << diag.format(sources);
  EXPECT_NEAR(p->end, 3.0, 1e-12);  // the same motion at half speed takes twice the time
}

TEST_F(Planning, MoveToPutsTheToolOnTheTarget) {
  auto p = plan("  - {type: arm6, name: R}\n  - {type: drum, name: D, location: [1.2, 0.3, 0]}\n",
                "  - {device: R, move_to: {target: D.top, offset: {xyz: [0, 0, 0.2], rpy: [180, 0, 0]}}}\n"
                "  - {device: R, move_to: {target: D.top, offset: {rpy: [180, 0, 0]}}, path: linear, speed: 0.1 m/s}\n"
                "  - {device: R, grasp: D}\n  - {device: R, move_joints: home}\n  - {device: R, release: {}}\n");
  ASSERT_TRUE(p) << diag.format(sources);
  ASSERT_FALSE(p->failure) << p->failure->message;
  Eigen::Vector3d top(1.2, 0.3, 0.851);
  EXPECT_LT((tool(*p, "R", p->steps[0].end).translation() - (top + Eigen::Vector3d(0, 0, 0.2))).norm(), 1e-4);
  EXPECT_LT((tool(*p, "R", p->steps[1].end).translation() - top).norm(), 1e-4);
  // The linear descent stays on the vertical line through the drum's top, pointing down.
  for (double u = 0.1; u < 1; u += 0.1) {
    double t = p->steps[1].start + u * (p->steps[1].end - p->steps[1].start);
    Eigen::Isometry3d X = tool(*p, "R", t);
    EXPECT_LT((X.translation().head<2>() - top.head<2>()).norm(), 1e-3) << u;
    EXPECT_NEAR(X.linear().col(2).z(), -1, 1e-3);
  }
  // 0.2 m at 0.1 m/s: at least 2 s.
  EXPECT_GE(p->steps[1].end - p->steps[1].start, 2.0);
}

TEST_F(Planning, UnreachableTargetsEndThePlanWithAFailure) {
  auto p = plan("  - {type: arm6, name: R}\n  - {type: drum, name: D, location: [4, 0, 0]}\n",
                "  - {device: R, move_to: {target: D.top}}\n  - wait: 1 s\n");
  ASSERT_TRUE(p) << diag.format(sources);
  ASSERT_TRUE(p->failure);
  EXPECT_EQ(p->failure->kind, EventKind::Unreachable);
  EXPECT_EQ(p->failure->step, 0u);
  EXPECT_GT(p->failure->position_error, 2.0);
}

TEST_F(Planning, BadStepsAreInputErrors) {
  std::string lib = type_dir({{"turntable", kTurntable}});
  const std::string objects = "  - {type: turntable, name: T}\n  - {type: drum, name: D, location: [3, 0, 0]}\n";
  const std::pair<const char*, const char*> cases[] = {
      {"  - {device: T, move_joints: {b: 3}}\n", "'b' is not a joint of T"},
      {"  - {device: T, move_joints: {a: 200}}\n", "outside its limits [-170 deg, 170 deg]"},
      {"  - {device: T, grasp: D}\n", "grasp: the tool of T is 1.714 m from D (at most 0.02 m)"},
      {"  - {device: T, release: {}}\n", "holds nothing"},
      {"  - {device: Tt, move_joints: home}\n", "did you mean 'T'"},
      {"  - {device: D, move_joints: home}\n", "not a device"},
  };
  for (const auto& [steps, fragment] : cases) {
    diag = Diagnostics();
    plan(objects, steps, lib);
    ASSERT_TRUE(diag.has_errors()) << steps;
    EXPECT_NE(diag.errors()[0].message.find(fragment), std::string::npos) << diag.errors()[0].message;
  }
}

TEST_F(Planning, ParallelGroupsEndWithTheirLastMember) {
  std::string lib = type_dir({{"turntable", kTurntable}});
  auto p = plan("  - {type: turntable, name: T1}\n  - {type: turntable, name: T2, location: [5, 0, 0]}\n",
                "  - parallel:\n      - {device: T1, move_joints: {a: 90}}\n      - {device: T2, move_joints: {a: 10}}\n"
                "  - {device: T2, move_joints: {a: 0}}\n", lib);
  ASSERT_TRUE(p) << diag.format(sources);
  EXPECT_NEAR(p->steps[0].end, 1.5, 1e-12);                     // the group
  EXPECT_NEAR(p->steps[3].start, 1.5, 1e-12);                   // the next step waits for it
  EXPECT_NEAR(p->steps[2].end, 2 * std::sqrt(10.0 / 180), 1e-9);  // T2's short move
}

}  // namespace
}  // namespace sscs::testing

namespace sscs::testing {
namespace {

TEST_F(Planning, MoveToEndsAtItsTargetForEveryDeviceKind) {
  // Property: for every standard device kind, random reachable targets (the tool pose at random
  // joint values within limits), one after another, each move_to's planned end puts the tool on
  // its target within 1 mm. The crane's travel (18 m) and the vehicles' x and y (±100 m) are
  // prismatic strokes far longer than 2π m.
  const char* kinds[] = {"arm6", "ur5", "gantry", "bridge_crane", "forklift", "agv"};
  std::mt19937_64 rng(5);
  for (const char* kind : kinds) {
    SCOPED_TRACE(kind);
    const Device& d = only_device(kind);
    Chain chain(d);
    std::string steps;
    std::vector<Eigen::Isometry3d> targets;
    for (int i = 0; i < 6; ++i) {
      Eigen::VectorXd q = d.joint_values(&wc_.values[wc_.objects[0].first_slot + kFirstAttributeSlot]);
      for (int k = 0; k < chain.size(); ++k) {
        double lo = std::max(chain.lower(k), -3.0), hi = std::min(chain.upper(k), chain.revolute(k) ? 3.0 : 40.0);
        q[chain.device_index(k)] = std::uniform_real_distribution<double>(lo, hi)(rng);
      }
      Eigen::Isometry3d X = geometry_.objects[0].X_world_object * d.tool_pose(q);
      targets.push_back(X);
      steps += move_to_step(X);
    }
    auto p = plan_steps(steps);
    ASSERT_TRUE(p) << diag.format(sources);
    ASSERT_FALSE(p->failure) << p->failure->message;
    ASSERT_EQ(p->steps.size(), targets.size());
    for (size_t i = 0; i < targets.size(); ++i) {
      Eigen::Isometry3d reached = tool(*p, "D", p->steps[i].end);
      EXPECT_LE((reached.translation() - targets[i].translation()).norm(), 1e-3) << "step " << i;
      EXPECT_LE(Eigen::AngleAxisd(reached.linear().transpose() * targets[i].linear()).angle(), 1e-3) << "step " << i;
    }
  }
}

TEST_F(Planning, ATracksRangeHoldsEveryJointValueBetweenTwoTimes) {
  // Property: for every standard device kind, random moves (joint-space and linear paths), and
  // random spans of time across them (within a move, across moves and the holds between), every
  // joint value the track takes in the span, sampled finely, lies in Track::range's box, and the
  // box is no larger than the values taken (its bounds are reached, within the sampling).
  const char* kinds[] = {"arm6", "ur5", "gantry", "bridge_crane", "forklift", "agv"};
  std::mt19937_64 rng(29);
  for (const char* kind : kinds) {
    SCOPED_TRACE(kind);
    const Device& d = only_device(kind);
    Chain chain(d);
    Eigen::VectorXd q = d.joint_values(&wc_.values[wc_.objects[0].first_slot + kFirstAttributeSlot]);
    std::string steps;
    for (int i = 0; i < 6; ++i) {
      for (int k = 0; k < chain.size(); ++k) {
        // Small moves from the last pose: a linear path between them exists.
        double lo = std::max(chain.lower(k), q[chain.device_index(k)] - 0.4), hi = std::min(chain.upper(k), q[chain.device_index(k)] + 0.4);
        q[chain.device_index(k)] = std::uniform_real_distribution<double>(lo, hi)(rng);
      }
      steps += move_to_step(geometry_.objects[0].X_world_object * d.tool_pose(q), i % 2 ? ", path: linear" : "");
      if (i == 2) steps += "  - {wait: 0.5 s}\n";
    }
    auto p = plan_steps(steps);
    ASSERT_TRUE(p) << diag.format(sources);
    ASSERT_FALSE(p->failure) << p->failure->message;
    const Track& track = *p->track(wc_.find_object("D"));
    ASSERT_GE(track.segments.size(), 6u);
    EXPECT_TRUE(std::any_of(track.segments.begin(), track.segments.end(), [](const Segment& s) { return !s.waypoints.empty(); }));
    std::uniform_real_distribution<double> when(0, p->end);
    for (int trial = 0; trial < 60; ++trial) {
      double a = when(rng), b = trial % 3 ? a + std::uniform_real_distribution<double>(0, 0.3)(rng) : when(rng);
      if (a > b) std::swap(a, b);
      Eigen::VectorXd lo, hi;
      track.range(a, b, lo, hi);
      Eigen::VectorXd seen_lo = track.at(a), seen_hi = seen_lo;
      for (int k = 0; k <= 2000; ++k) {
        const Eigen::VectorXd q_t = track.at(a + (b - a) * k / 2000);
        seen_lo = seen_lo.cwiseMin(q_t);
        seen_hi = seen_hi.cwiseMax(q_t);
      }
      for (int j = 0; j < d.dof(); ++j) {
        EXPECT_LE(lo[j], seen_lo[j] + 1e-12) << "joint " << j << " over [" << a << ", " << b << "]";
        EXPECT_GE(hi[j], seen_hi[j] - 1e-12) << "joint " << j << " over [" << a << ", " << b << "]";
        // Tight: what the fine samples miss is at most a sample's worth of motion.
        EXPECT_GE(lo[j], seen_lo[j] - 0.01 * (seen_hi[j] - seen_lo[j]) - 1e-9) << "joint " << j;
        EXPECT_LE(hi[j], seen_hi[j] + 0.01 * (seen_hi[j] - seen_lo[j]) + 1e-9) << "joint " << j;
      }
    }
  }
}

// A planar arm of three links (1 m, 1 m, 0.5 m) turning about z: a tool pose has an elbow-left
// and an elbow-right solution, its wrist at the same point.
const char* kPlanar3 = R"(sscs: 1
type: planar3
kind: device
parts:
  - {name: base, geometry: [{cylinder: {radius: 0.1, length: 0.4, xyz: [0, 0, 0.2]}}]}
  - name: l1
    parent: base
    joint: {name: a, type: revolute, axis: [0, 0, 1], xyz: [0, 0, 0.5], limits: {min: -170, max: 170, velocity: 90, acceleration: 180}}
    geometry: [{box: {size: [1, 0.05, 0.05], xyz: [0.5, 0, 0]}}]
  - name: l2
    parent: l1
    joint: {name: b, type: revolute, axis: [0, 0, 1], xyz: [1, 0, 0], limits: {min: -170, max: 170, velocity: 90, acceleration: 180}}
    geometry: [{box: {size: [1, 0.05, 0.05], xyz: [0.5, 0, 0]}}]
  - name: l3
    parent: l2
    joint: {name: c, type: revolute, axis: [0, 0, 1], xyz: [1, 0, 0], limits: {min: -170, max: 170, velocity: 90, acceleration: 180}}
    geometry: [{box: {size: [0.5, 0.05, 0.05], xyz: [0.25, 0, 0]}}]
tool: {part: l3, xyz: [0.5, 0, 0]}
)";

TEST_F(Planning, MoveToChoosesJointValuesWhereTheCarriedLoadIsFree) {
  // The tool to (1.5, 0) facing +x: the wrist at (1, 0), the elbow at (0.5, +0.866) or (0.5,
  // -0.866). The held bracket (a block at the tool, a plate on it) reaches back beside the wrist, on the side of the
  // elbow the empty arm takes: there it is in the second link, so carrying it the arm takes the
  // other elbow.
  const std::string to = "  - {device: A, move_to: {target: {xyz: [1.5, 0, 0.5]}}}\n";
  auto elbow_side = [&](const std::string& bracket_side, bool carrying) {
    const std::string bracket = fmt::format("sscs: 1\ntype: bracket\ngeometry:\n  - box: {{size: [0.05, 0.05, 0.05], xyz: [0.025, 0, 0]}}\n"
                                            "  - box: {{size: [0.3, 0.25, 0.05], xyz: [-0.65, {}, 0]}}\n",
                                            bracket_side == "+" ? 0.275 : -0.275);
    diag = Diagnostics{};
    auto p = plan("  - {type: planar3, name: A}\n  - {type: bracket, name: B, location: [2.5, 0, 0.5]}\n",
                  (carrying ? "  - {device: A, grasp: B}\n" : "") + to, type_dir({{"planar3", kPlanar3}, {"bracket", bracket}}));
    EXPECT_TRUE(p && !p->failure) << diag.format(sources);
    if (!p || p->failure) return 0.0;
    const Eigen::VectorXd q = p->track(wc_.find_object("A"))->at(p->end);
    EXPECT_LT((tool(*p, "A", p->end).translation() - Eigen::Vector3d(1.5, 0, 0.5)).norm(), 1e-3);
    return std::sin(q[0]);  // the elbow's y
  };
  const double empty = elbow_side("+", false);
  ASSERT_NE(empty, 0.0);
  const std::string side = empty > 0 ? "+" : "-";
  EXPECT_GT(elbow_side(side, false) * empty, 0) << "the empty arm does not care where the bracket is";
  EXPECT_LT(elbow_side(side, true) * empty, 0) << "carrying the bracket on the elbow's side, the other elbow";
  EXPECT_GT(elbow_side(side == "+" ? "-" : "+", true) * empty, 0) << "the bracket on the other side leaves the first elbow free";
}

}  // namespace
}  // namespace sscs::testing
