#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <numbers>
#include <regex>
#include <set>

#include <fmt/format.h>

#include "core/inertia.h"
#include "geometry/collision.h"
#include "geometry/geometry.h"
#include "kinematics/ik.h"
#include "vault_fixture.h"
#include "core/units.h"

namespace sscs::testing {
namespace {


class Kinematics : public VaultTest {
 public:
  /// Compiles a vault holding one device `R` (and whatever else `objects` adds).
  std::shared_ptr<const Device> device(const std::string& objects, const std::string& library = "") {
    if (!library.empty()) options.library_dirs = {library};
    wc_ = must_compile("objects:\n" + objects);
    geometry_ = build_geometry(wc_, diag);
    EXPECT_FALSE(diag.has_errors()) << diag.format(sources);
    int r = wc_.find_object("R");
    EXPECT_GE(r, 0);
    return r < 0 ? nullptr : geometry_.objects[r].device;
  }
  Workcell wc_;
  GeometryModel geometry_;
};

// A planar two-link arm: hand-computed forward kinematics.
const char* kPlanar = R"(sscs: 1
type: planar2
kind: device
parts:
  - {name: base, geometry: [{cylinder: {radius: 0.6, length: 1, xyz: [0, 0, 0.5]}}]}
  - {name: upper, parent: base, joint: {name: a, type: revolute, axis: [0, 0, 1], xyz: [0, 0, 0.5], limits: {min: -170, max: 170}}}
  - name: fore
    parent: upper
    joint: {name: b, type: revolute, axis: [0, 0, 1], xyz: [1, 0, 0], limits: {min: -170, max: 170}}
    geometry: [{box: {size: [0.5, 0.1, 0.1], xyz: [0.25, 0, 0]}}]
  - {name: slide, parent: fore, joint: {name: c, type: prismatic, axis: [1, 0, 0], xyz: [0.5, 0, 0], limits: {min: 0, max: 0.3}}}
tool: {part: slide, xyz: [0.1, 0, 0]}
)";

TEST_F(Kinematics, ForwardKinematicsMatchesHandComputedPoses) {
  auto d = device("  - {type: planar2, name: R, a: 90, b: -90, c: 0.2}\n", type_dir({{"planar2", kPlanar}}));
  ASSERT_TRUE(d);
  ASSERT_EQ(d->dof(), 3);
  Eigen::VectorXd q(3);
  q << 90 * kRadPerDeg, -90 * kRadPerDeg, 0.2;
  // Upper link along +y (1 m), forearm back along +x: 0.5 + 0.2 slide + 0.1 tool.
  Eigen::Isometry3d tool = d->tool_pose(q);
  EXPECT_TRUE(tool.translation().isApprox(Eigen::Vector3d(0.8, 1.0, 0.5), 1e-12)) << tool.translation().transpose();
  EXPECT_TRUE(tool.linear().isApprox(Eigen::Matrix3d::Identity(), 1e-12));
  // The instance's joint values come from its attributes; the tool is a frame of the object.
  const ObjectGeometry& g = geometry_.objects[wc_.find_object("R")];
  ASSERT_TRUE(g.frame("tool"));
  EXPECT_TRUE(g.frame("tool")->translation().isApprox(Eigen::Vector3d(0.8, 1.0, 0.5), 1e-12));
  ASSERT_TRUE(g.frame("fore"));
  EXPECT_TRUE(g.frame("fore")->translation().isApprox(Eigen::Vector3d(0, 1.0, 0.5), 1e-12));
  // The chain agrees with the tree.
  Chain chain(*d);
  EXPECT_TRUE(chain.forward(chain.from_device(q)).isApprox(tool, 1e-12));
}

TEST_F(Kinematics, JacobianMatchesFiniteDifferences) {
  auto d = device("  - {type: arm6, name: R}\n");
  ASSERT_TRUE(d);
  Chain chain(*d);
  Eigen::VectorXd q(6);
  q << 0.3, -0.4, 0.5, 1.0, -0.7, 0.2;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J;
  Eigen::Isometry3d X = chain.forward(q, J);
  for (int k = 0; k < 6; ++k) {
    Eigen::VectorXd dq = q;
    dq[k] += 1e-7;
    Eigen::Matrix<double, 6, 1> e = pose_error(X, chain.forward(dq)) / 1e-7;
    EXPECT_TRUE(e.isApprox(J.col(k), 1e-5)) << k << ": " << e.transpose() << " vs " << J.col(k).transpose();
  }
}

TEST_F(Kinematics, ArmDimensionsAreTheDataSheets) {
  // ABB IRB 2600-20/1.65 at zero: wrist centre at (a1 + d4, 0, d1 + a2 + a3); flange d6 beyond.
  auto d = device("  - {type: arm6, name: R, tool_length: 0}\n");
  ASSERT_TRUE(d);
  Eigen::Isometry3d tool = d->tool_pose(Eigen::VectorXd::Zero(6));
  EXPECT_TRUE(tool.translation().isApprox(Eigen::Vector3d(0.150 + 0.795 + 0.085, 0, 0.445 + 0.700 + 0.115), 1e-12))
      << tool.translation().transpose();
  EXPECT_NEAR(d->joint(1).lower, -95 * kRadPerDeg, 1e-12);
  EXPECT_NEAR(d->joint(2).upper, 75 * kRadPerDeg, 1e-12);
  EXPECT_NEAR(d->joint(0).velocity, 175 * kRadPerDeg, 1e-12);
}

TEST_F(Kinematics, InverseKinematicsRoundTripsRandomReachablePoses) {
  auto d = device("  - {type: arm6, name: R}\n");
  ASSERT_TRUE(d);
  Chain chain(*d);
  IkOptions opt;
  opt.time_limit = 1e9;  // the iteration budget ends a solve, not the machine's speed
  opt.position_tol = 1e-6;
  opt.angle_tol = 1e-6;
  std::srand(7);
  int solved = 0, rounding = 0;
  const int n = 300;
  Eigen::VectorXd nominal = Eigen::VectorXd::Zero(6);
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd q(6);
    for (int k = 0; k < 6; ++k)
      q[k] = chain.lower(k) + (chain.upper(k) - chain.lower(k)) * (std::rand() / (RAND_MAX + 1.0));
    Eigen::Isometry3d target = chain.forward(q);
    IkResult r = solve_ik(chain, target, nominal, opt);
    if (!r.ok()) continue;
    ++solved;
    // The solution is within limits and really reaches the pose.
    for (int k = 0; k < 6; ++k) {
      EXPECT_GE(r.q[k], chain.lower(k) - 1e-12);
      EXPECT_LE(r.q[k], chain.upper(k) + 1e-12);
    }
    Eigen::Matrix<double, 6, 1> e = pose_error(chain.forward(r.q), target);
    EXPECT_LE(e.head<3>().norm(), 1e-6);
    EXPECT_LE(e.tail<3>().norm(), 1e-6);
    // The reported error is the solution's, and polished: rounding, but within a hair of a
    // singularity (docs/devices.md), where it still holds the tolerance.
    EXPECT_NEAR(r.position_error, e.head<3>().norm(), 1e-12);
    rounding += r.position_error <= 1e-9 && r.angle_error <= 1e-9;
  }
  EXPECT_GE(solved, n - 1);
  EXPECT_GE(rounding, solved - 1) << "of " << solved << " solutions";
}

TEST_F(Kinematics, SolutionNearestTheSeed) {
  auto d = device("  - {type: arm6, name: R}\n");
  ASSERT_TRUE(d);
  Chain chain(*d);
  Eigen::VectorXd q(6);
  q << 0.2, 0.3, -0.4, 0.5, 0.6, 0.1;
  // Seeded next to a solution, the solver returns that one, not another branch or a turn away.
  Eigen::VectorXd seed = q + Eigen::VectorXd::Constant(6, 0.05);
  IkResult r = solve_ik(chain, chain.forward(q), seed, {});
  ASSERT_TRUE(r.ok());
  EXPECT_LT((r.q - q).norm(), 1e-4);
  // Joint 4 turns +-400 deg: seeded a turn up, the answer is a turn up too.
  seed[3] += 2 * kPi;
  r = solve_ik(chain, chain.forward(q), seed, {});
  ASSERT_TRUE(r.ok());
  EXPECT_NEAR(r.q[3], q[3] + 2 * kPi, 1e-4);
}

TEST_F(Kinematics, ExtraAttemptsFindANearerSolution) {
  auto d = device("  - {type: arm6, name: R}\n");
  ASSERT_TRUE(d);
  Chain chain(*d);
  Eigen::VectorXd q(6), seed(6);
  q << 0.5, 0.4, -0.6, 1.2, -0.9, 0.3;
  seed << -2.5, 1.5, 0.8, -3.0, 1.5, -4.0;  // far from q: the first solution found may be another branch
  IkOptions opt;
  opt.time_limit = 1e9;  // the iteration budget ends a solve, not the machine's speed
  IkResult first = solve_ik(chain, chain.forward(q), seed, opt);
  opt.extra_attempts = 30;
  IkResult nearest = solve_ik(chain, chain.forward(q), seed, opt);
  ASSERT_TRUE(first.ok());
  ASSERT_TRUE(nearest.ok());
  EXPECT_LE((nearest.q - seed).norm(), (first.q - seed).norm() + 1e-12);
  EXPECT_GT(nearest.attempts, first.attempts);
  EXPECT_LE(pose_error(chain.forward(nearest.q), chain.forward(q)).norm(), 1e-5);
}

TEST_F(Kinematics, PositionOnlyMode) {
  auto d = device("  - {type: arm6, name: R}\n");
  ASSERT_TRUE(d);
  Chain chain(*d);
  IkOptions opt;
  opt.time_limit = 1e9;  // the iteration budget ends a solve, not the machine's speed
  opt.orientation = false;
  Eigen::Isometry3d target = Eigen::Isometry3d::Identity();
  target.translation() = Eigen::Vector3d(1.0, 0.5, 0.8);
  target.linear() = rpy_to_rotation(1, 2, 3);  // ignored
  IkResult r = solve_ik(chain, target, Eigen::VectorXd::Zero(6), opt);
  ASSERT_TRUE(r.ok());
  EXPECT_LE((chain.forward(r.q).translation() - target.translation()).norm(), 1e-5);
}

TEST_F(Kinematics, UnreachableAndSingularTargetsReturnPromptly) {
  auto d = device("  - {type: arm6, name: R}\n");
  ASSERT_TRUE(d);
  Chain chain(*d);
  IkOptions opt;
  opt.time_limit = 1e9;  // the iteration budget ends a solve, not the machine's speed
  // Far outside the workspace: rejected at once, with the remaining error measured.
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translation() = Eigen::Vector3d(5, 0, 1);
  IkResult r = solve_ik(chain, far, Eigen::VectorXd::Zero(6), opt);
  EXPECT_EQ(r.status, IkResult::Status::Unreachable);
  EXPECT_LE(r.attempts, 1);
  EXPECT_GT(r.position_error, 3.0);
  // Just outside the arm's stretch (a singular, fully extended pose): the whole budget, bounded.
  Eigen::VectorXd stretched(6);
  stretched << 0, 90 * kRadPerDeg, -atan2(0.795, 0.115), 0, 0, 0;  // upper arm and forearm in line, horizontal
  Eigen::Isometry3d edge = chain.forward(stretched);
  edge.translation() += edge.translation().normalized() * 0.01;
  r = solve_ik(chain, edge, Eigen::VectorXd::Zero(6), opt);
  EXPECT_EQ(r.status, IkResult::Status::Unreachable);
  EXPECT_LE(r.iterations, opt.iterations_per_attempt * opt.max_attempts);
  EXPECT_GT(r.position_error, 0.005);
  // Exactly the singular pose itself is reached.
  r = solve_ik(chain, chain.forward(stretched), Eigen::VectorXd::Zero(6), opt);
  EXPECT_TRUE(r.ok()) << r.position_error;
  // The iteration budget ends a solve even with no time limit to speak of.
  opt.time_limit = 1e9;
  opt.max_attempts = 3;
  r = solve_ik(chain, edge, Eigen::VectorXd::Zero(6), opt);
  EXPECT_EQ(r.attempts, 3);
  EXPECT_FALSE(r.timed_out);  // the budget, not the clock, ended it: a verdict may rest on it
  // The clock backstop ending a search is said, so no "unreachable" verdict rests on it.
  opt.time_limit = 0;
  opt.max_attempts = 200;
  r = solve_ik(chain, edge, Eigen::VectorXd::Zero(6), opt);
  EXPECT_EQ(r.status, IkResult::Status::Unreachable);
  EXPECT_TRUE(r.timed_out);
  EXPECT_EQ(r.attempts, 1);
}

TEST_F(Kinematics, JointLimitsBoundTheSolution) {
  auto d = device("  - {type: planar2, name: R}\n", type_dir({{"planar2", kPlanar}}));
  ASSERT_TRUE(d);
  Chain chain(*d);
  // The tip sweeps an annulus of radii 0.19 (b = 170 deg, slide out) to 1.9 m; a point nearer
  // the axis needs the forearm folded beyond its limit.
  Eigen::Isometry3d folded = Eigen::Isometry3d::Identity();
  folded.translation() = Eigen::Vector3d(0.15, 0.0, 0.5);  // needs b = 173 deg
  IkOptions opt;
  opt.time_limit = 1e9;  // the iteration budget ends a solve, not the machine's speed
  opt.orientation = false;
  IkResult r = solve_ik(chain, folded, Eigen::VectorXd::Zero(3), opt);
  EXPECT_EQ(r.status, IkResult::Status::Unreachable);
  Eigen::Isometry3d ok = Eigen::Isometry3d::Identity();
  ok.translation() = Eigen::Vector3d(1.2, 0.9, 0.5);
  r = solve_ik(chain, ok, Eigen::VectorXd::Zero(3), opt);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(d->within_limits(r.q));
}

TEST_F(Kinematics, JointValuesAreLimitedAttributes) {
  std::string err = first_error("objects:\n  - {type: arm6, name: R, j2: 160}\n");
  EXPECT_NE(err.find("j2"), std::string::npos) << err;
  EXPECT_NE(err.find("155"), std::string::npos) << err;
}

TEST_F(Kinematics, SelfCollisionBetweenNonAdjacentParts) {
  // Folded back, the forearm enters the base column; the upper link, adjacent to both, never counts.
  std::string lib = type_dir({{"planar2", kPlanar}});
  auto d = device("  - {type: planar2, name: R, b: 170}\n", lib);
  ASSERT_TRUE(d);
  CollisionWorld world(geometry_);
  auto hits = world.self_collisions(wc_.find_object("R"));
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_EQ(d->parts[hits[0].part].name, "base");
  EXPECT_EQ(d->parts[hits[0].other_part].name, "fore");
  EXPECT_GT(hits[0].depth, 0.05);
  // Stretched, nothing collides.
  device("  - {type: planar2, name: R, b: 0}\n", lib);
  CollisionWorld stretched(geometry_);
  EXPECT_TRUE(stretched.self_collisions(wc_.find_object("R")).empty());
}

}  // namespace
}  // namespace sscs::testing

namespace sscs::testing {
namespace {

class Urdf : public Kinematics {};

TEST_F(Urdf, UrdfAndNativeDescriptionsGiveTheSameKinematics) {
  // library/urdf/ur5.urdf (DH frames) against a native type aligned with the base at zero.
  options.package_paths = {std::string(SSCS_TEST_DATA) + "/urdf/packages"};
  options.library_dirs = {std::string(SSCS_TEST_DATA) + "/urdf"};
  Workcell wc = must_compile("objects:\n  - {type: ur5, name: U}\n  - {type: ur5_native, name: N}\n");
  GeometryModel g = build_geometry(wc, diag);
  ASSERT_FALSE(diag.has_errors()) << diag.format(sources);
  const Device& u = *g.objects[wc.find_object("U")].device;
  const Device& n = *g.objects[wc.find_object("N")].device;
  ASSERT_EQ(u.dof(), 6);
  ASSERT_EQ(n.dof(), 6);
  EXPECT_EQ(u.parts[u.tool_part].name, "tool0");
  EXPECT_NEAR(u.joint(0).upper, 2 * kPi, 1e-12);
  EXPECT_NEAR(u.joint(0).velocity, kPi, 1e-12);
  EXPECT_NEAR(u.joint(5).effort, 28, 1e-12);
  EXPECT_NEAR(u.parts[2].mass, 8.393, 1e-12);
  ASSERT_TRUE(u.parts[2].com);
  // At zero the UR5 lies stretched along -x: a2 + a3 = -0.81725 m, wrist offsets d4, d5, d6.
  Eigen::Isometry3d zero = u.tool_pose(Eigen::VectorXd::Zero(6));
  EXPECT_TRUE(zero.translation().isApprox(Eigen::Vector3d(-0.81725, -0.10915 - 0.0823, 0.089159 - 0.09465), 1e-12))
      << zero.translation().transpose();
  std::srand(11);
  for (int i = 0; i < 200; ++i) {
    Eigen::VectorXd q = Eigen::VectorXd::Random(6) * kPi;
    Eigen::Isometry3d a = u.tool_pose(q), b = n.tool_pose(q);
    ASSERT_TRUE(a.isApprox(b, 1e-12)) << "q = " << q.transpose() << "\n" << a.matrix() << "\n" << b.matrix();
  }
}

TEST_F(Urdf, LinksJointsInertiasAndMeshesImport) {
  options.package_paths = {std::string(SSCS_TEST_DATA) + "/urdf/packages"};
  options.library_dirs = {std::string(SSCS_TEST_DATA) + "/urdf"};
  Workcell wc = must_compile("objects:\n  - {type: meshy, name: M, spin: 90, reach_out: 0.25}\n");
  GeometryModel g = build_geometry(wc, diag);
  ASSERT_FALSE(diag.has_errors()) << diag.format(sources);
  const Device& d = *g.objects[0].device;
  ASSERT_EQ(d.parts.size(), 3u);
  EXPECT_EQ(d.parts[1].joint.type, JointType::Revolute);  // continuous: no limits
  EXPECT_TRUE(std::isinf(d.parts[1].joint.lower));
  EXPECT_EQ(d.parts[2].joint.type, JointType::Prismatic);
  EXPECT_NEAR(d.parts[2].joint.upper, 0.5, 1e-12);
  EXPECT_NEAR(d.parts[0].mass, 10, 1e-12);
  ASSERT_TRUE(d.parts[0].inertia);
  EXPECT_NEAR((*d.parts[0].inertia)(2, 2), 0.3, 1e-12);
  EXPECT_EQ(d.parts[1].color, "#ff0000");
  EXPECT_EQ(d.parts[1].shapes[0].kind, Shape::Kind::Sphere);  // a visual-only link uses its visuals
  ASSERT_EQ(d.parts[2].shapes.size(), 1u);
  EXPECT_EQ(d.parts[2].shapes[0].kind, Shape::Kind::Mesh);
  // The tool defaults to the end of the longest chain; at spin 90 deg the slide points along +y.
  EXPECT_EQ(d.tool_part, 2);
  ASSERT_TRUE(g.objects[0].frame("tool"));
  EXPECT_TRUE(g.objects[0].frame("tool")->translation().isApprox(Eigen::Vector3d(0, 0.45, 0.3), 1e-12));
  // The mesh (a 0.1 m cube) is in the object's bounds there.
  EXPECT_NEAR(g.objects[0].bbox_world.max().y(), 0.5, 1e-9);
}


// Robots as vendors ship them (issue 19): tests/data/vendor holds a URDF in the ROS-Industrial
// layout (tool0 on fixed joints, a forearm that overlaps the wrist in every pose, soft limits, a
// continuous joint, a mimic finger) and the MoveIt SRDF that disables the overlapping pair.
class Vendor : public Kinematics {
 public:
  // (Formatted, not `std::string(SSCS_TEST_DATA) + "/vendor"`: GCC 12 warned of a memcpy out of
  // bounds there, a false positive that depends on the length of the clone's path.)
  const std::string data = fmt::format("{}/vendor", SSCS_TEST_DATA);
  const std::string urdf = fmt::format("{}/acme_rx6_support/urdf/rx6.urdf", data);
  const std::string srdf = fmt::format("{}/acme_rx6_moveit_config/config/rx6.srdf", data);
  /// A type file for the vendor's URDF, with `extra` lines (srdf:, joint_limits:).
  std::string rx6_type(const std::string& extra) {
    return "sscs: 1\ntype: rx6\nkind: device\nurdf: " + urdf + "\ntool: {part: tool0}\n" + extra;
  }
  /// The self-collisions of R at joint values `q` (radians, joints in file order).
  std::vector<Collision> self_collisions_at(const std::string& library, const std::string& joints) {
    options.library_dirs = {library};
    wc_ = must_compile("objects:\n  - {type: rx6, name: R" + joints + "}\n");
    geometry_ = build_geometry(wc_, diag);
    EXPECT_FALSE(diag.has_errors()) << diag.format(sources);
    CollisionWorld world(geometry_);
    return world.self_collisions(wc_.find_object("R"));
  }
};

TEST_F(Vendor, TheSrdfsDisabledPairsAreAllowedCollisions) {
  auto d = device("  - {type: rx6, name: R}\n", data + "/library");
  ASSERT_TRUE(d);
  EXPECT_EQ(d->parts[d->tool_part].name, "tool0");
  EXPECT_EQ(d->dof(), 8);  // six axes and two fingers (the mimic one imported as its own joint)
  const int l4 = d->find_part("link_4"), l6 = d->find_part("link_6");
  EXPECT_TRUE(d->may_touch(l4, l6));
  EXPECT_TRUE(d->may_touch(l6, l4));
  EXPECT_FALSE(d->may_touch(d->find_part("link_2"), l6));
  EXPECT_FALSE(d->adjacent(l4, l6));
}

TEST_F(Vendor, WithoutTheSrdfTheOverlapIsASelfCollisionInEveryPoseWithItNever) {
  const std::string with = data + "/library";
  const std::string without = type_dir({{"rx6", rx6_type("")}});
  std::srand(19);
  for (int i = 0; i < 20; ++i) {
    // Wrist joints anywhere in their limits: the forearm (link_4) always holds the wrist (link_6).
    double j4 = 3.1 * (2.0 * std::rand() / RAND_MAX - 1), j5 = 2.0 * (2.0 * std::rand() / RAND_MAX - 1);
    std::string joints = fmt::format(", joint_4: {} rad, joint_5: {} rad", j4, j5);
    auto hits = self_collisions_at(without, joints);
    bool pair = std::any_of(hits.begin(), hits.end(), [&](const Collision& c) {
      const Device& d = *geometry_.objects[wc_.find_object("R")].device;
      return d.parts[c.part].name == "link_4" && d.parts[c.other_part].name == "link_6";
    });
    EXPECT_TRUE(pair) << joints;
    for (const Collision& c : self_collisions_at(with, joints)) {
      const Device& d = *geometry_.objects[wc_.find_object("R")].device;
      EXPECT_FALSE(d.parts[c.part].name == "link_4" && d.parts[c.other_part].name == "link_6") << joints;
    }
  }
}

TEST_F(Vendor, WithoutAToolTheSrdfsEndEffectorNamesIt) {
  auto d = device("  - {type: rx6, name: R}\n",
                  type_dir({{"rx6", "sscs: 1\ntype: rx6\nkind: device\nurdf: " + urdf + "\nsrdf: " + srdf + "\n"}}));
  ASSERT_TRUE(d);
  EXPECT_EQ(d->parts[d->tool_part].name, "tool0");  // <end_effector parent_link="tool0">
  // Without the SRDF: the end of the longest chain (a finger here), as for any device.
  auto bare = device("  - {type: rx6, name: R}\n", type_dir({{"rx6", "sscs: 1\ntype: rx6\nkind: device\nurdf: " + urdf + "\n"}}));
  ASSERT_TRUE(bare);
  EXPECT_NE(bare->parts[bare->tool_part].name, "tool0");
}

TEST_F(Vendor, SoftLimitsBoundTheJointsUnlessHardIsChosen) {
  auto soft = device("  - {type: rx6, name: R}\n", data + "/library");
  ASSERT_TRUE(soft);
  EXPECT_DOUBLE_EQ(soft->joint(0).lower, -2.5);  // <safety_controller> within <limit> ±2.967
  EXPECT_DOUBLE_EQ(soft->joint(0).upper, 2.5);
  EXPECT_DOUBLE_EQ(soft->joint(1).upper, 1.6);  // no safety controller: the hard limit
  EXPECT_TRUE(std::isinf(soft->joint(5).upper));  // continuous
  auto hard = device("  - {type: rx6, name: R}\n", type_dir({{"rx6", rx6_type("joint_limits: hard\n")}}));
  ASSERT_TRUE(hard);
  EXPECT_DOUBLE_EQ(hard->joint(0).lower, -2.967);
  EXPECT_DOUBLE_EQ(hard->joint(0).upper, 2.967);
  // A joint value between the soft and hard limits is refused under the soft ones, as any value
  // beyond a joint's limits.
  options.library_dirs = {data + "/library"};
  EXPECT_NE(first_error("objects:\n  - {type: rx6, name: R, joint_1: 2.7 rad}\n").find("joint_1"), std::string::npos);
}

TEST_F(Vendor, ALimitAsSscsTypesPrintsItIsThatLimit) {
  // `sscs types` prints joint_1's soft limits, +-2.5 rad, as +-143.239448783 deg (12 digits):
  // copied back, a hair beyond the limit, they are the limit; a value beyond by more is refused.
  options.library_dirs = {data + "/library"};
  Workcell wc = must_compile("objects:\n  - {type: rx6, name: R, joint_1: 143.239448783 deg}\n"
                             "  - {type: rx6, name: S, joint_1: -143.239448783 deg, location: [2, 0, 0]}\n");
  EXPECT_EQ(value(wc, "R.joint_1"), 2.5);
  EXPECT_EQ(value(wc, "S.joint_1"), -2.5);
  diag = Diagnostics();
  EXPECT_EQ(first_error("objects:\n  - {type: rx6, name: R, joint_1: 143.2395 deg}\n"),
            "'joint_1' of 'R' is 143.2395 deg, above the max 143.239448783 deg of type 'rx6'");
}

TEST_F(Vendor, DefaultDisabledAndReEnabledCollisionsOfTheSrdfCount) {
  // MoveIt's <disable_default_collisions link=> allows that link to touch every other;
  // <enable_collisions> takes a pair of those back; a <disable_collisions> pair stays allowed even
  // when enabled too (MoveIt applies the disabled pairs last).
  auto dir = std::filesystem::path(type_dir({}));
  std::ofstream(dir / "rx6.srdf") << "<robot name=\"acme_rx6\">\n"
                                     "  <disable_default_collisions link=\"link_2\"/>\n"
                                     "  <enable_collisions link1=\"link_6\" link2=\"link_2\"/>\n"
                                     "  <disable_collisions link1=\"link_4\" link2=\"link_6\" reason=\"Default\"/>\n"
                                     "  <enable_collisions link1=\"link_4\" link2=\"link_6\"/>\n"
                                     "</robot>\n";
  std::ofstream(dir / "rx6.yaml") << rx6_type("srdf: rx6.srdf\n");
  auto d = device("  - {type: rx6, name: R}\n", dir.string());
  ASSERT_TRUE(d);
  EXPECT_TRUE(diag.warnings().empty()) << diag.format(sources);
  const int l2 = d->find_part("link_2"), l4 = d->find_part("link_4"), l6 = d->find_part("link_6");
  EXPECT_TRUE(d->may_touch(l2, d->find_part("link_5")));
  EXPECT_TRUE(d->may_touch(d->find_part("finger_left"), l2));
  EXPECT_FALSE(d->may_touch(l2, l6));
  EXPECT_TRUE(d->may_touch(l4, l6));
}

TEST_F(Vendor, AnSrdfNamingAnotherRobotOrNoOneToolIsWarnedAbout) {
  auto dir = std::filesystem::path(type_dir({}));
  std::ofstream(dir / "rx6.srdf") << "<robot name=\"acme_rx9\">\n"
                                     "  <group name=\"arm\"><chain base_link=\"base_link\" tip_link=\"tool0\"/></group>\n"
                                     "  <group name=\"hand\"><chain base_link=\"gripper\" tip_link=\"finger_left\"/></group>\n"
                                     "</robot>\n";
  std::ofstream(dir / "rx6.yaml") << "sscs: 1\ntype: rx6\nkind: device\nurdf: " + urdf + "\nsrdf: rx6.srdf\n";
  auto d = device("  - {type: rx6, name: R}\n", dir.string());
  ASSERT_TRUE(d);
  ASSERT_EQ(diag.warnings().size(), 2u) << diag.format(sources);
  EXPECT_EQ(diag.warnings()[0].message, "this SRDF is for robot 'acme_rx9', but the URDF is robot 'acme_rx6' (is the SRDF another robot's?)");
  EXPECT_EQ(diag.warnings()[1].message,
            "this SRDF names 0 end effector parent links () and 2 chain tips (tool0, finger_left): no one tool; the tool is "
            "the end of the longest chain (write tool: in the type to choose)");
  EXPECT_EQ(sources.path(diag.warnings()[0].mark.file), (dir / "rx6.srdf").string());
}

TEST_F(Vendor, AnSrdfOfAnotherRobotIsAnErrorInTheSrdf) {
  auto dir = std::filesystem::path(type_dir({}));
  std::ofstream(dir / "other.srdf") << "<robot name=\"other\">\n  <disable_collisions link1=\"link_4\" link2=\"forearm\" reason=\"Never\"/>\n</robot>\n";
  std::ofstream(dir / "rx6.yaml") << rx6_type("srdf: other.srdf\n");
  options.library_dirs = {dir.string()};
  std::string e = first_error("objects:\n  - {type: rx6, name: R}\n");
  EXPECT_EQ(e, "this <disable_collisions> names 'forearm', which is no link of 'rx6' (is the SRDF another robot's?)");
  // The robot's name differs too: a warning at the SRDF's <robot>, beside the error.
  ASSERT_EQ(diag.warnings().size(), 1u);
  EXPECT_EQ(diag.warnings()[0].message, "this SRDF is for robot 'other', but the URDF is robot 'acme_rx6' (is the SRDF another robot's?)");
  EXPECT_EQ(diag.warnings()[0].mark.line, 1u);
  ASSERT_FALSE(diag.errors().empty());
  EXPECT_EQ(sources.path(diag.errors()[0].mark.file), (dir / "other.srdf").string());
  EXPECT_EQ(diag.errors()[0].mark.line, 2u);
}

TEST_F(Vendor, AnSrdfToolThatIsNoLinkIsReportedWhereTheTypeIsUsed) {
  // The SRDF's end effector names a link the URDF lacks: an error in the SRDF for a vault that
  // uses the type; a vault of the same library folder that does not use it is unaffected.
  auto dir = std::filesystem::path(type_dir({}));
  std::ofstream(dir / "other.srdf") << "<robot name=\"other\">\n  <end_effector name=\"hand\" parent_link=\"hand_flange\" group=\"hand\"/>\n</robot>\n";
  std::ofstream(dir / "rx6.yaml") << "sscs: 1\ntype: rx6\nkind: device\nurdf: " + urdf + "\nsrdf: other.srdf\n";
  options.library_dirs = {dir.string()};
  must_compile("objects:\n  - {type: drum, name: D}\n");
  std::string e = first_error("objects:\n  - {type: rx6, name: R}\n");
  EXPECT_EQ(e, "the tool this SRDF names, 'hand_flange', is no link of 'rx6' (is the SRDF another robot's?)");
  // The robot's name differs too: a warning at the SRDF's <robot>, beside the error.
  ASSERT_EQ(diag.warnings().size(), 1u);
  EXPECT_EQ(diag.warnings()[0].message, "this SRDF is for robot 'other', but the URDF is robot 'acme_rx6' (is the SRDF another robot's?)");
  EXPECT_EQ(diag.warnings()[0].mark.line, 1u);
  ASSERT_FALSE(diag.errors().empty());
  EXPECT_EQ(sources.path(diag.errors()[0].mark.file), (dir / "other.srdf").string());
  EXPECT_EQ(diag.errors()[0].mark.line, 2u);
}

TEST_F(Vendor, VisualsAreDrawnWithTheirMaterialsWhileChecksUseTheCollisionShapes) {
  options.library_dirs = {data + "/library"};
  Workcell wc = must_compile("objects:\n  - {type: rx6, name: R}\n");
  GeometryModel checked = build_geometry(wc, diag);
  GeometryModel drawn = build_geometry(wc, diag, nullptr, {.visuals = true, .contacts = nullptr});
  ASSERT_FALSE(diag.has_errors()) << diag.format(sources);
  const ObjectGeometry& c = checked.objects[0];
  const ObjectGeometry& v = drawn.objects[0];
  EXPECT_TRUE(c.visual_shapes.empty());  // checks and sweeps build no visuals
  EXPECT_EQ(v.shapes.size(), c.shapes.size());
  const Device& d = *v.device;
  const int l1 = d.find_part("link_1"), l3 = d.find_part("link_3");
  auto of_part = [](const std::vector<Shape>& shapes, int part) {
    std::vector<const Shape*> out;
    for (const Shape& s : shapes)
      if (s.part == part) out.push_back(&s);
    return out;
  };
  // link_1: one collision hull; drawn as its two visuals, each in its own material's colour.
  ASSERT_EQ(of_part(v.shapes, l1).size(), 1u);
  auto visuals = of_part(v.drawn_shapes(), l1);
  ASSERT_EQ(visuals.size(), 2u);
  EXPECT_EQ(visuals[0]->kind, Shape::Kind::Box);
  EXPECT_EQ(visuals[0]->color, "#f57800");
  EXPECT_EQ(visuals[1]->kind, Shape::Kind::Cylinder);
  EXPECT_EQ(visuals[1]->color, "#4d4d4d");
  // link_2's visual is a DAE whose materials colour it: a shape per colour, in the file's colours.
  auto arm = of_part(v.drawn_shapes(), d.find_part("link_2"));
  ASSERT_EQ(arm.size(), 2u);
  std::set<std::string> colours = {arm[0]->color, arm[1]->color};
  EXPECT_EQ(colours, (std::set<std::string>{"#1a1a1a", "#f57800"}));
  // link_3's visual is a textured DAE: the sides in the image's yellow, the end caps in its grey.
  auto wrist = of_part(v.drawn_shapes(), l3);
  ASSERT_EQ(wrist.size(), 2u);
  EXPECT_EQ((std::set<std::string>{wrist[0]->color, wrist[1]->color}), (std::set<std::string>{"#222222", "#ffcc00"}));
  EXPECT_EQ(of_part(v.shapes, l3)[0]->kind, Shape::Kind::Sphere);  // the collision shape checks use
  // link_5 has no visual: drawn as its collision sphere.
  const int l5 = d.find_part("link_5");
  ASSERT_EQ(of_part(v.drawn_shapes(), l5).size(), 1u);
  EXPECT_EQ(of_part(v.drawn_shapes(), l5)[0]->kind, Shape::Kind::Sphere);
}

TEST_F(Vendor, ADegenerateShapeIsSkippedWithAWarningNamingFileAndLink) {
  // Franka's panda-gazebo.urdf: a zero-length cylinder on a link.
  const std::string dir = rx6_dir([](std::string& text) {
    const std::string base = "<link name=\"base_link\">";
    text.replace(text.find(base), base.size(),
                 base + "\n    <collision><geometry><cylinder radius=\"0.1\" length=\"0\"/></geometry></collision>");
  });
  auto d = device("  - {type: rx6, name: R}\n", dir);
  ASSERT_TRUE(d);
  ASSERT_EQ(diag.warnings().size(), 1u) << diag.format(sources);
  EXPECT_EQ(diag.warnings()[0].message, "link 'base_link': its <collision> cylinder has length 0: skipped, for it has no volume");
  // At the cylinder's element in the URDF, the line after <link name="base_link">.
  EXPECT_EQ(sources.path(diag.warnings()[0].mark.file), dir + "/rx6.urdf");
  const std::string& urdf = sources.text(diag.warnings()[0].mark.file);
  const size_t link_line = std::count(urdf.begin(), urdf.begin() + urdf.find("<link name=\"base_link\">"), '\n') + 1;
  EXPECT_EQ(diag.warnings()[0].mark.line, link_line + 1);
  EXPECT_EQ(d->parts[d->find_part("base_link")].shapes.size(), 1u);  // the vendor's own cylinder stays
}

TEST_F(Vendor, WhatTheUrdfLeavesToDefaultsIsWarnedAtItsLine) {
  // A URDF's velocity="0" and effort="0" say "not given"; a mimic of no joint; a safety
  // controller with one soft limit (the other is 0, as the format and MoveIt have it).
  std::string original;
  const std::string dir = rx6_dir([&](std::string& text) {
    auto replace = [&](const std::string& from, const std::string& to) { text.replace(text.find(from), from.size(), to); };
    replace("<limit lower=\"-1.6\" upper=\"1.6\" effort=\"300\" velocity=\"2.6\"/>",
            "<limit lower=\"-1.6\" upper=\"1.6\" effort=\"0\" velocity=\"0.0\"/>");
    replace("<mimic joint=\"finger_left_joint\"", "<mimic joint=\"finger_joint\"");
    replace("soft_lower_limit=\"-2.5\" soft_upper_limit=\"2.5\"", "soft_upper_limit=\"2.5\"");
    original = text;
  });
  auto line_of = [&](const std::string& what) { return 1u + std::count(original.begin(), original.begin() + original.find(what), '\n'); };
  auto d = device("  - {type: rx6, name: R}\n", dir);
  ASSERT_TRUE(d);
  ASSERT_EQ(diag.warnings().size(), 4u) << diag.format(sources);
  std::map<std::string, uint32_t> warnings;
  for (const Diagnostic& w : diag.warnings()) {
    EXPECT_EQ(sources.path(w.mark.file), dir + "/rx6.urdf") << w.message;
    warnings[w.message] = w.mark.line;
  }
  EXPECT_EQ(warnings["joint 'joint_2': <limit velocity=\"0\"> is taken as not given: it moves at the default 90 deg/s (write its "
                     "speed to time runs)"], line_of("effort=\"0\""));
  EXPECT_EQ(warnings["joint 'joint_2': <limit effort=\"0\"> is taken as not given: a run drives it with the default torque, 1e5 N m"],
            line_of("effort=\"0\""));
  EXPECT_EQ(warnings["joint 'finger_right_joint': <mimic joint=\"finger_joint\"> names no joint of this robot (sscs moves mimic "
                     "joints on their own, so nothing changes here)"], line_of("<mimic"));
  EXPECT_EQ(warnings["joint 'joint_1': <safety_controller> gives no soft_lower_limit: it is 0, as the URDF format defines it and "
                     "MoveIt reads it (write it, or choose `joint_limits: hard`)"], line_of("<safety_controller"));
  EXPECT_DOUBLE_EQ(d->joint(0).lower, 0.0);
  EXPECT_DOUBLE_EQ(d->joint(0).upper, 2.5);
  EXPECT_EQ(d->joint(1).velocity, 0.0);  // the run's default speed applies
  EXPECT_EQ(d->joint(1).effort, 0.0);
}

TEST_F(Vendor, PackagesAreFoundByTheirManifestsNameInANestedWorkspace) {
  // A colcon workspace: the package's folder is named after its git repository, not the package;
  // ROS finds it by package.xml's <name>, and so does sscs (it did not: "no package").
  namespace fs = std::filesystem;
  const fs::path ws = fs::temp_directory_path() / "sscs_ws_test";
  fs::remove_all(ws);
  const fs::path pkg = ws / "src" / "acme" / "rx6-support-git";
  fs::create_directories(pkg);
  fs::copy(data + "/acme_rx6_support/meshes", pkg / "meshes", fs::copy_options::recursive);
  std::ofstream(pkg / "package.xml") << "<?xml version=\"1.0\"?>\n<package format=\"3\">\n  <name>acme_rx6_support</name>\n"
                                        "  <version>1.0.0</version>\n</package>\n";
  const std::string dir = rx6_dir([&](std::string& text) {
    const std::string absolute = data + "/acme_rx6_support/meshes/visual/";
    for (size_t at; (at = text.find(absolute)) != std::string::npos;)
      text.replace(at, absolute.size(), "package://acme_rx6_support/meshes/visual/");
  });
  options.package_paths = {ws.string()};
  auto d = device("  - {type: rx6, name: R}\n", dir);
  ASSERT_TRUE(d) << diag.format(sources);
  EXPECT_TRUE(diag.warnings().empty()) << diag.format(sources);  // its visual meshes were found
  // Without the manifest only a folder named like the package would do: the visual is not found
  // (a warning: the link has collision shapes), naming the package.
  const fs::path plain = fs::temp_directory_path() / "sscs_ws_test_plain";
  fs::remove_all(plain);
  fs::create_directories(plain / "src");
  fs::copy(ws / "src", plain / "src", fs::copy_options::recursive);
  fs::remove(plain / "src" / "acme" / "rx6-support-git" / "package.xml");
  diag = Diagnostics();
  options.package_paths = {plain.string()};
  d = device("  - {type: rx6, name: R}\n", dir);
  ASSERT_TRUE(d);
  ASSERT_FALSE(diag.warnings().empty());
  EXPECT_NE(diag.warnings()[0].message.find("no package 'acme_rx6_support'"), std::string::npos) << diag.warnings()[0].message;
  fs::remove_all(ws);
  fs::remove_all(plain);
}

TEST_F(Vendor, AZeroAxisAnUnderflowAndAnUnnamedSrdfAreReportedInTheirFiles) {
  struct Case {
    const char* written;
    const char* made;
    const char* error;
  };
  const Case cases[] = {
      {"<axis xyz=\"0 1 0\"/>", "<axis xyz=\"0 0 0\"/>",
       "joint 'joint_2': <axis xyz=\"0 0 0\"> is the zero vector: a joint needs a direction (write its unit axis, such as \"0 0 1\")"},
      {"<mass value=\"20\"/>", "<mass value=\"1e-400\"/>",
       "<mass value>: expected a finite mass in kg (not negative), found '1e-400': '1e-400' is closer to 0 than a double can hold (write 0)"},
  };
  for (const Case& c : cases) {
    const std::string dir = rx6_dir([&](std::string& text) { text.replace(text.find(c.written), std::strlen(c.written), c.made); });
    diag = Diagnostics();
    options.library_dirs = {dir};
    EXPECT_EQ(first_error("objects:\n  - {type: rx6, name: R}\n"), c.error);
    ASSERT_FALSE(diag.errors().empty());
    EXPECT_EQ(sources.path(diag.errors()[0].mark.file), dir + "/rx6.urdf");
  }
  auto dir = std::filesystem::path(type_dir({}));
  std::ofstream(dir / "rx6.srdf") << "<robot>\n  <disable_collisions link1=\"link_4\" link2=\"link_6\"/>\n</robot>\n";
  std::ofstream(dir / "rx6.yaml") << rx6_type("srdf: rx6.srdf\n");
  diag = Diagnostics();
  auto d = device("  - {type: rx6, name: R}\n", dir.string());
  ASSERT_TRUE(d);
  ASSERT_EQ(diag.warnings().size(), 1u) << diag.format(sources);
  EXPECT_EQ(diag.warnings()[0].message, "this SRDF's <robot> has no name (MoveIt requires one: the URDF's, 'acme_rx6')");
}

TEST_F(Vendor, EveryNumberOfTheUrdfThatIsNotFiniteIsAnErrorAtItsLine) {
  // urdfdom drops a <collision> whose shape it cannot read and takes "nan" as a number: each
  // number the vendor's file writes (sizes, origins, axes, limits, inertias, colours), made nan,
  // inf, 1e999 or no number in turn, is an error at its line of the URDF, never a robot that
  // lost a solid.
  std::string original;
  rx6_dir([&](std::string& text) { original = text; });
  const std::regex number(R"(-?[0-9.][0-9.e+-]*)");
  const std::regex numbers(R"(\s*-?[0-9.][0-9.e+-]*(\s+-?[0-9.][0-9.e+-]*)*\s*)");
  const std::regex attribute(R"re((\w+)="([^"]*)")re");
  const char* bad[] = {"nan", "inf", "1e999", "-nan", "0x"};
  size_t tried = 0;
  for (auto a = std::sregex_iterator(original.begin(), original.end(), attribute); a != std::sregex_iterator(); ++a) {
    const std::string value = (*a)[2];
    if (!std::regex_match(value, numbers) || (*a)[1] == "version") continue;  // names, files, the XML declaration
    auto n = std::sregex_iterator(value.begin(), value.end(), number);
    std::string edited_value = value;
    edited_value.replace(n->position(), n->length(), bad[tried % std::size(bad)]);
    const size_t at = a->position(2);
    const std::string dir = rx6_dir([&](std::string& text) { text.replace(at, value.size(), edited_value); });
    const uint32_t line = 1 + std::count(original.begin(), original.begin() + at, '\n');
    diag = Diagnostics();
    options.library_dirs = {dir};
    const std::string e = first_error("objects:\n  - {type: rx6, name: R}\n");
    ASSERT_FALSE(diag.errors().empty()) << (*a)[0] << " made " << edited_value << " passed";
    const Diagnostic& first = diag.errors()[0];
    EXPECT_EQ(sources.path(first.mark.file), dir + "/rx6.urdf") << e;
    EXPECT_EQ(first.mark.line, line) << e;
    EXPECT_NE(e.find("'" + edited_value + "'"), std::string::npos) << e;
    ++tried;
  }
  EXPECT_GT(tried, 100u);  // every number of the file was tried
}

TEST_F(Vendor, AShapeUrdfdomWouldDropIsAnError) {
  struct Case {
    const char* written;
    const char* made;
    const char* error;
  };
  const Case cases[] = {
      {"<box size=\"0.2 0.2 0.2\"/>", "<box/>", "<box> needs a size attribute (3 finite lengths in m), found none"},
      {"<box size=\"0.2 0.2 0.2\"/>", "<capsule radius=\"0.1\" length=\"0.2\"/>",
       "<geometry> needs one of <box>, <cylinder>, <sphere> or <mesh>, found <capsule>"},
      {"<box size=\"0.2 0.2 0.2\"/>", "", "<geometry> needs one of <box>, <cylinder>, <sphere> or <mesh>, found nothing"},
      {"<box size=\"0.2 0.2 0.2\"/>", "<box size=\"0.2 0.2\"/>",
       "<box size>: expected 3 finite lengths in m (not negative), found '0.2 0.2' (2 of them)"},
      {"<mass value=\"20\"/>", "<mass value=\"-20\"/>",
       "<mass value>: expected a finite mass in kg (not negative), found '-20': -20 is negative"},
      {"<color rgba=\"0.96 0.47 0.0 1.0\"/>", "<color rgba=\"0.96 1.47 0.0 1.0\"/>",
       "<color rgba>: expected 4 finite colour channels (each 0 to 1), found '0.96 1.47 0.0 1.0': 1.47 is outside 0 to 1"},
  };
  for (const Case& c : cases) {
    const std::string dir = rx6_dir([&](std::string& text) { text.replace(text.find(c.written), std::strlen(c.written), c.made); });
    diag = Diagnostics();
    options.library_dirs = {dir};
    EXPECT_EQ(first_error("objects:\n  - {type: rx6, name: R}\n"), c.error);
  }
}

TEST_F(Vendor, ALimitWithoutLowerOrUpperIsWarnedOfAtItsLine) {
  // URDF reads a missing lower or upper as 0: a joint whose <limit> gives neither cannot move,
  // and was taken silently as [0, 0].
  const std::string dir = rx6_dir([](std::string& text) {
    const std::string limit = "<limit lower=\"-2.967\" upper=\"2.967\"";
    text.replace(text.find(limit), limit.size(), "<limit");
  });
  auto d = device("  - {type: rx6, name: R}\n", dir);
  ASSERT_TRUE(d);
  ASSERT_EQ(diag.warnings().size(), 1u) << diag.format(sources);
  EXPECT_NE(diag.warnings()[0].message.find("<limit> gives no lower or upper: URDF reads it as 0, so the joint's range is [0, 0] and it "
                                            "cannot move"), std::string::npos) << diag.warnings()[0].message;
  EXPECT_EQ(sources.path(diag.warnings()[0].mark.file), dir + "/rx6.urdf");
}

TEST_F(Vendor, AnInertiaOdeCannotIntegrateIsAWarningAndABox) {
  const std::string dir = rx6_dir([](std::string& text) {
    auto replace = [&](const std::string& from, const std::string& to) { text.replace(text.find(from), from.size(), to); };
    replace("<mass value=\"1\"/><inertia ixx=\"0.001\" ixy=\"0\" ixz=\"0\" iyy=\"0.001\" iyz=\"0\" izz=\"0.001\"/>",
            "<mass value=\"1\"/><inertia ixx=\"0\" ixy=\"0\" ixz=\"0\" iyy=\"0\" iyz=\"0\" izz=\"0\"/>");  // link_5
    replace("<mass value=\"4\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/>",
            "<mass value=\"4\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.05\"/>");  // link_3
  });
  auto d = device("  - {type: rx6, name: R}\n", dir);
  ASSERT_TRUE(d);
  ASSERT_EQ(diag.warnings().size(), 2u) << diag.format(sources);
  std::set<std::string> warnings = {diag.warnings()[0].message, diag.warnings()[1].message};
  EXPECT_TRUE(warnings.count("link 'link_5': its <inertial> is not a physical body (its inertia is all zero): "
                                   "simulated as a box around its shapes of 1 kg")) << *warnings.rbegin();
  EXPECT_TRUE(warnings.count("link 'link_3': its <inertial> is not a physical body (its principal moments 0.01, "
                                   "0.01, 0.05 kg m^2 break the triangle inequality (the largest above the sum of the others)): "
                                   "simulated as a box around its shapes of 4 kg")) << *warnings.begin();
  EXPECT_FALSE(d->parts[d->find_part("link_5")].inertia);
  EXPECT_TRUE(d->parts[d->find_part("link_4")].inertia);
  // "Physical" but beyond what ODE integrates (it aborted): 20 kg with moments of 1e-15 kg m^2, a
  // mass of 1e-20 kg.
  EXPECT_NE(unphysical_inertia(20, Eigen::Matrix3d::Identity() * 1e-15).find("radius of gyration"), std::string::npos);
  EXPECT_NE(unphysical_inertia(1e-20, Eigen::Matrix3d::Identity() * 1e-22).find("beyond the 1e-6 to 1e7 kg"), std::string::npos);
  EXPECT_NE(unphysical_inertia(20, Eigen::Matrix3d::Identity() * 1e300).find("radius of gyration"), std::string::npos);
  EXPECT_EQ(unphysical_inertia(0.002, Eigen::Matrix3d::Identity() * 6.67e-7), "");  // a 2 g finger
}

}  // namespace
}  // namespace sscs::testing
