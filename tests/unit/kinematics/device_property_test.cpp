// Property tests over every standard device and the URDF examples: random joint configurations
// within limits -> forward kinematics -> inverse kinematics must reach the pose, within limits,
// with prismatic joints never shifted; and the tool exemption covers the part the tool is bolted to.
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>

#include "geometry/geometry.h"
#include "kinematics/ik.h"
#include "vault_fixture.h"
#include "core/units.h"

namespace sscs::testing {
namespace {

namespace fs = std::filesystem;

class DeviceProperty : public VaultTest {
 public:
  void SetUp() override {
    options.package_paths = {std::string(SSCS_TEST_DATA) + "/urdf/packages"};
    options.library_dirs = {std::string(SSCS_TEST_DATA) + "/urdf"};
  }
  const Device* device(const std::string& type) {
    diag = Diagnostics{};
    wc_ = must_compile("objects:\n  - {type: " + type + ", name: R}\n");
    geometry_ = build_geometry(wc_, diag);
    EXPECT_FALSE(diag.has_errors()) << diag.format(sources);
    int r = wc_.find_object("R");
    return r < 0 || !geometry_.objects[r].device ? nullptr : geometry_.objects[r].device.get();
  }
  Workcell wc_;
  GeometryModel geometry_;
};

/// A uniformly random configuration within the chain's limits (an unlimited joint: a turn
/// either way, or 20 m).
Eigen::VectorXd random_q(const Chain& chain, std::mt19937_64& rng) {
  Eigen::VectorXd q(chain.size());
  for (int k = 0; k < chain.size(); ++k) {
    double span = chain.revolute(k) ? kPi : 20.0;
    double lo = std::isfinite(chain.lower(k)) ? chain.lower(k) : -span;
    double hi = std::isfinite(chain.upper(k)) ? chain.upper(k) : span;
    q[k] = std::uniform_real_distribution<double>(lo, hi)(rng);
  }
  return q;
}

TEST_F(DeviceProperty, TheStandardLibraryHasTheDeviceKindsThisTestCovers) {
  auto devices = standard_devices();
  for (const char* kind : {"agv", "arm6", "bridge_crane", "forklift", "gantry", "ur5"})
    EXPECT_NE(std::find(devices.begin(), devices.end(), kind), devices.end()) << kind;
}

TEST_F(DeviceProperty, InverseKinematicsReachesEveryRandomPoseOfEveryDevice) {
  auto devices = standard_devices();
  devices.push_back("meshy");       // URDF: continuous and prismatic joints, a package:// mesh
  devices.push_back("ur5_native");  // the UR5 written natively
  std::mt19937_64 rng(20261123);
  for (const std::string& type : devices) {
    SCOPED_TRACE(type);
    const Device* d = device(type);
    ASSERT_TRUE(d);
    Chain chain(*d);
    ASSERT_GT(chain.size(), 0);
    int revolute = 0;
    for (int k = 0; k < chain.size(); ++k) revolute += chain.revolute(k);
    IkOptions opt;
    opt.position_tol = 1e-6;
    opt.angle_tol = 1e-6;
    // The iteration budget ends a solve; the wall-clock backstop must not (a sanitizer build runs
    // several times slower, and a verdict must not depend on the machine's speed).
    opt.time_limit = 1e9;
    const int n = 150;
    int solved = 0;
    for (int i = 0; i < n; ++i) {
      Eigen::VectorXd q = random_q(chain, rng), seed = random_q(chain, rng);
      Eigen::Isometry3d target = chain.forward(q);
      IkResult r = solve_ik(chain, target, seed, opt);
      if (!r.ok()) {
        if (std::getenv("SSCS_DEBUG_IK"))
          std::cerr << type << " failed: q = " << q.transpose() << " seed = " << seed.transpose() << " status "
                    << static_cast<int>(r.status) << " attempts " << r.attempts << " err " << r.position_error << "\n";
        continue;
      }
      ++solved;
      for (int k = 0; k < chain.size(); ++k) {
        EXPECT_GE(r.q[k], chain.lower(k) - 1e-12) << "joint " << k;
        EXPECT_LE(r.q[k], chain.upper(k) + 1e-12) << "joint " << k;
      }
      // The pose reached is the one asked for, at the values returned (not values shifted after).
      Eigen::Matrix<double, 6, 1> e = pose_error(chain.forward(r.q), target);
      EXPECT_LE(e.head<3>().norm(), 1e-6) << "q = " << q.transpose() << "\nsolution = " << r.q.transpose();
      EXPECT_LE(e.tail<3>().norm(), 1e-6);
      // With at most one revolute joint the solution is unique: prismatic values are exactly q's.
      if (revolute <= 1) {
        for (int k = 0; k < chain.size(); ++k) {
          if (!chain.revolute(k)) {
            EXPECT_NEAR(r.q[k], q[k], 1e-6) << "prismatic joint " << k;
          }
        }
      }
    }
    // Arms have several branches and singular poses; the solver still finds nearly all of them.
    EXPECT_GE(solved, n * (revolute >= 5 ? 0.97 : 1.0)) << solved << " of " << n;
  }
}

TEST_F(DeviceProperty, APrismaticStrokeLongerThanATurnIsNeverWrapped) {
  // The bridge crane's travel is 17 m at its defaults: a target at 12 m seeded at 0 must end at 12 m, not 12 - 2π.
  const Device* d = device("bridge_crane");
  ASSERT_TRUE(d);
  Chain chain(*d);
  for (double x : {12.0, 2 * kPi + 0.01, 16.9, 0.2}) {
    Eigen::VectorXd q = Eigen::VectorXd::Zero(chain.size());
    q[0] = x;
    q[2] = 3.0;
    IkResult r = solve_ik(chain, chain.forward(q), Eigen::VectorXd::Zero(chain.size()), IkOptions{});
    ASSERT_TRUE(r.ok()) << x;
    EXPECT_NEAR(r.q[0], x, 1e-6);
    EXPECT_NEAR(r.q[2], 3.0, 1e-6);
  }
}

TEST_F(DeviceProperty, EveryPartFixedToTheToolBelongsToTheTool) {
  // The UR5 URDF hangs tool0 off wrist_3_link through a fixed joint (as ROS-Industrial robots
  // hang tool0 off link_6): the flange belongs to the tool, the forearm does not.
  const Device* d = device("ur5");
  ASSERT_TRUE(d);
  std::vector<char> tool = d->tool_parts();
  EXPECT_EQ(d->parts[d->tool_part].name, "tool0");
  int flange = d->parts[d->tool_part].parent;
  ASSERT_GE(flange, 0);
  EXPECT_EQ(d->parts[d->tool_part].joint.type, JointType::Fixed);
  EXPECT_TRUE(tool[d->tool_part]);
  EXPECT_TRUE(tool[flange]) << d->parts[flange].name;
  for (size_t p = 0; p < d->parts.size(); ++p) {
    // Exactly the flange's rigid body and what hangs off it.
    bool below_flange = false;
    for (int a = static_cast<int>(p); a >= 0; a = d->parts[a].parent) below_flange = below_flange || a == flange;
    EXPECT_EQ(static_cast<bool>(tool[p]), below_flange) << d->parts[p].name;
  }
  // The gantry's gripper hangs off its z carriage by a fixed mount: the carriage is the tool's too.
  d = device("gantry");
  ASSERT_TRUE(d);
  tool = d->tool_parts();
  int top = d->tool_part;
  while (d->parts[top].joint.type == JointType::Fixed && d->parts[top].parent >= 0) top = d->parts[top].parent;
  EXPECT_TRUE(tool[top]) << d->parts[top].name;
  EXPECT_FALSE(tool[0]);
}

TEST_F(DeviceProperty, EveryVerticalAxisLiftsTheDevicesRatedLoad) {
  // The gantry was rated for 500 kg with 3000 N on its vertical axis: it could not lift the
  // 368 kg a cart weighed (the tool stayed on the floor, a tracking_error). A vertical prismatic
  // joint with an effort limit must lift the rated load (`payload` or `capacity`) and the parts
  // it moves at its full acceleration.
  constexpr double kG = 9.80665;
  int rated_devices = 0;
  for (const std::string& type : standard_devices()) {
    SCOPED_TRACE(type);
    const Device* dev = device(type);
    ASSERT_NE(dev, nullptr);
    const Object& obj = wc_.objects[wc_.find_object("R")];
    double rated = -1;
    for (const char* name : {"payload", "capacity"})
      if (int a = wc_.types[obj.type].find_attribute(name); a >= 0) rated = wc_.values[obj.first_slot + kFirstAttributeSlot + a];
    if (rated < 0) continue;
    ++rated_devices;
    const auto X = dev->part_poses(Eigen::VectorXd::Zero(dev->dof()));
    for (int q = 0; q < dev->dof(); ++q) {
      const int p = dev->joint_parts[q];
      const Joint& j = dev->joint(q);
      const Eigen::Vector3d axis = (X[p].linear() * j.axis).normalized();
      if (j.type != JointType::Prismatic || j.effort <= 0 || std::abs(axis.z()) < 0.9 || dev->kinematic) continue;
      double moved = rated;
      for (size_t k = 0; k < dev->parts.size(); ++k)
        for (int up = static_cast<int>(k); up >= 0; up = dev->parts[up].parent)
          if (up == p) {
            moved += dev->parts[k].mass;
            break;
          }
      EXPECT_GE(j.effort, moved * (kG + j.acceleration)) << j.name << " moves " << moved << " kg";
    }
  }
  EXPECT_GE(rated_devices, 3);
}

}  // namespace
}  // namespace sscs::testing
