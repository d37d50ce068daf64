#include <cmath>
#include <random>

#include <fmt/format.h>

#include <ode/ode.h>

#include "geometry/geometry.h"
#include "model/device.h"
#include "simulate/profile.h"
#include "simulate/world.h"
#include "vault_fixture.h"

namespace sscs::testing {
namespace {

constexpr double kG = 9.80665;

const char* kTable = R"(sscs: 1
type: table
attributes:
  height: {type: length, default: 0.5}
geometry:
  - box: {size: [1, 1, height], xyz: [0, 0, "height/2"]}
)";

class Physics : public VaultTest {
 public:
  /// A physics world of the vault's objects, with object `dynamic` set free.
  std::unique_ptr<PhysicsWorld> world_of(const std::string& objects, const std::string& dynamic) {
    wc = must_compile("objects:\n" + objects);
    geometry = build_geometry(wc, diag);
    auto world = std::make_unique<PhysicsWorld>(wc, geometry, PhysicsOptions{});
    d = wc.find_object(dynamic);
    world->make_dynamic(d);
    return world;
  }
  Workcell wc;
  GeometryModel geometry;
  int d = -1;
};

TEST_F(Physics, AReleasedDrumFallsFreelyAndComesToRestOnTheSupport) {
  options.library_dirs = {type_dir({{"table", kTable}})};
  auto w = world_of("  - {type: table, name: T}\n  - {type: drum, name: D, location: [0.1, 0, 1.0], fill_mass: 180}\n", "D");
  PhysicsWorld& world = *w;
  EXPECT_NEAR(world.mass(d), 22 + 180, 1e-9);  // tare + fill
  // Free fall from 0.5 m above the table: z = z0 - g t^2 / 2 (semi-implicit Euler adds g t dt / 2).
  const double contact_time = std::sqrt(2 * 0.5 / kG);
  bool touched_early = false;
  while (world.time() < contact_time - 0.01) {
    world.step();
    double t = world.time();
    EXPECT_NEAR(world.pose(d).translation().z(), 1.0 - kG * t * t / 2, 3e-3) << t;
    touched_early = touched_early || !world.contacts().empty();
  }
  EXPECT_FALSE(touched_early);
  // Then it lands and rests on the table top (its origin is its bottom), upright, still.
  bool landed = false;
  while (world.time() < 3.0) {
    world.step();
    for (const PhysicsContact& c : world.contacts()) landed = landed || (c.a == wc.find_object("T") && c.b == d);
  }
  EXPECT_TRUE(landed);
  Eigen::Isometry3d X = world.pose(d);
  EXPECT_NEAR(X.translation().z(), 0.5, 5e-3);
  EXPECT_NEAR(X.translation().x(), 0.1, 5e-3);
  EXPECT_NEAR(X.linear().col(2).z(), 1.0, 1e-3);
  EXPECT_LT(world.velocity(d).norm(), 1e-3);
  EXPECT_TRUE(world.at_rest(d));
}

TEST_F(Physics, ADrumLandsOnAMeshPallet) {
  // The EUR pallet is a triangle mesh (library/meshes/eur_pallet.ply), 144 mm high.
  auto w = world_of("  - {type: pallet, name: P}\n  - {type: drum, name: D, location: [0.4, 0.4, 0.6]}\n", "D");
  PhysicsWorld& world = *w;
  // Dropped 0.46 m onto the deck boards it rocks for a while (ODE's cylinder-mesh contacts are
  // sparse); it must still end upright on the deck, at rest.
  while (world.time() < 6.0) world.step();
  EXPECT_NEAR(world.pose(d).translation().z(), 0.144, 5e-3);
  EXPECT_NEAR(world.pose(d).linear().col(2).z(), 1.0, 1e-3);
  EXPECT_TRUE(world.at_rest(d));
}

TEST_F(Physics, MeshesSetDownOnMeshesStayWhereTheyWereSet) {
  // A hooped drum (a 48-sided lathe mesh) set down on the pallet's deck boards (a mesh), on the
  // floor, and a pallet on the floor: ODE reports such pairs' contacts in triangle order, and the
  // first 8 of them lay on one side of the rim; the drum rocked and walked (3 cm in 20 s, 54 deg
  // of turn on a lifted pallet) and never came to rest. Placements spread over the deck.
  struct Case {
    std::string objects, free;
    Eigen::Vector3d at;
  };
  std::vector<Case> cases;
  for (double x : {0.35, 0.6, 0.85})
    for (double y : {0.32, 0.48})
      for (double yaw : {0.0, 17.0})
        cases.push_back({fmt::format("  - {{type: pallet, name: P}}\n  - {{type: drum_hooped, name: D, location: [{}, {}, 0.1445], orientation: [0, 0, {}]}}\n", x, y, yaw),
                         "D", {x, y, 0.144}});
  cases.push_back({"  - {type: drum_hooped, name: D, location: [2, 2, 0.0005]}\n", "D", {2, 2, 0}});
  cases.push_back({"  - {type: pallet, name: D, location: [2, 2, 0.0005], orientation: [0, 0, 30]}\n", "D", {2, 2, 0}});
  for (const Case& c : cases) {
    auto w = world_of(c.objects, c.free);
    PhysicsWorld& world = *w;
    while (world.time() < 4.0) world.step();
    const Eigen::Isometry3d X = world.pose(d);
    EXPECT_LT((X.translation() - c.at).norm(), 1e-3) << c.objects << X.translation().transpose();
    EXPECT_GT(X.linear().col(2).z(), std::cos(1e-3)) << c.objects;
    EXPECT_TRUE(world.at_rest(d)) << c.objects;
  }
}

TEST_F(Physics, ADrumStandsOnADrumOnOneAxis) {
  // ODE's cylinder collider asserts "d != 0" for two cylinders on one axis and aborted the run.
  auto w = world_of("  - {type: drum, name: Low}\n  - {type: drum, name: D, location: [0, 0, 0.8515]}\n", "D");
  while (w->time() < 2.0) w->step();
  EXPECT_NEAR(w->pose(d).translation().z(), 0.851, 1e-3);
  EXPECT_NEAR(w->pose(d).translation().head<2>().norm(), 0, 1e-4);
  EXPECT_TRUE(w->at_rest(d));
}

TEST_F(Physics, LoadsDroppedOntoEveryPositionOfEveryLevelOfARackRestThere) {
  // Each rack of the library at its defaults and at other sizes: a load let go 2 cm above every
  // slot frame lands on that level (beams or deck) and rests there, upright, where it was let go.
  struct Case {
    std::string rack, load;
    bool turned;  // a pallet's 1.2 m side across the frame depth: yawed 90 deg, its origin is a corner
  };
  for (const Case& c : {Case{"{type: drum_rack, name: K}", "drum", false},
                        Case{"{type: drum_rack, name: K, bays: 2, levels: 4, level_height: 1.1, first_beam_height: 0.3}", "drum_hooped", false},
                        Case{"{type: drum_rack, name: K, bays: 1, levels: 2, positions: 1, depth: 0.7, beam_width: 0.12}", "drum", false},
                        Case{"{type: pallet_rack, name: K, bays: 2}", "pallet", true},
                        Case{"{type: rack, name: K, levels: 4, level_pitch: 1.1}", "drum", false}}) {
    wc = must_compile("objects:\n  - " + c.rack + "\n");
    GeometryModel rack = build_geometry(wc, diag);
    std::vector<std::pair<std::string, Eigen::Vector3d>> slots;
    for (const auto& [name, X] : rack.objects[0].frames_world)
      if (name.starts_with("slot_")) slots.emplace_back(name, X.translation());
    ASSERT_GE(slots.size(), 2u) << c.rack;
    std::string objects = "  - " + c.rack + "\n";
    for (const auto& [name, at] : slots) {
      const Eigen::Vector3d origin = c.turned ? Eigen::Vector3d(at.x() + 0.4, at.y() - 0.6, at.z()) : at;
      objects += fmt::format("  - {{type: {}, name: L_{}, location: [{}, {}, {}], orientation: [0, 0, {}]}}\n", c.load, name, origin.x(),
                             origin.y(), origin.z() + 0.02, c.turned ? 90 : 0);
    }
    auto world = world_of(objects, "L_" + slots[0].first);
    for (const auto& [name, at] : slots) world->make_dynamic(wc.find_object("L_" + name));
    while (world->time() < 3.0) world->step();
    for (const auto& [name, at] : slots) {
      const int o = wc.find_object("L_" + name);
      const Eigen::Isometry3d X = world->pose(o);
      const Eigen::Vector3d expected = c.turned ? Eigen::Vector3d(at.x() + 0.4, at.y() - 0.6, at.z()) : at;
      EXPECT_LT((X.translation() - expected).norm(), 3e-3) << c.rack << " " << name << ": " << X.translation().transpose();
      EXPECT_GT(X.linear().col(2).z(), std::cos(2e-3)) << c.rack << " " << name;
      EXPECT_TRUE(world->at_rest(o)) << c.rack << " " << name;
    }
  }
}

TEST_F(Physics, AKeepOutZoneIsNoSolidToAFallingDrum) {
  // A guard zone pushes nothing and meets no free body: a drum let go above one falls through it
  // to the floor, and no contact with the zone is reported.
  auto w = world_of("  - {type: keepout_zone, name: Z, length: 2, width: 2, height: 1}\n  - {type: drum, name: D, location: [1, 1, 1.5]}\n", "D");
  bool touched_zone = false;
  while (w->time() < 2.0) {
    w->step();
    for (const PhysicsContact& c : w->contacts()) touched_zone = touched_zone || c.a == wc.find_object("Z") || c.b == wc.find_object("Z");
  }
  EXPECT_FALSE(touched_zone);
  EXPECT_NEAR(w->pose(d).translation().z(), 0, 2e-3);
  EXPECT_TRUE(w->at_rest(d));
}

TEST_F(Physics, AnOdeFailureIsAnExceptionNotAnAbort) {
  // Its errors and internal assertions aborted the process (exit 134, a staging folder left).
  auto w = world_of("  - {type: drum, name: D}\n", "D");
  EXPECT_THROW(dDebug(1, "assertion \"%s\" failed", "d != 0"), PhysicsFailure);
  EXPECT_THROW(dError(2, "bad %d", 2), PhysicsFailure);
}

TEST_F(Physics, FloorsTurnWithTheirRoomAndGroundLiesBesideAPit) {
  // A mezzanine turned 45 deg had the box around it for a floor: a drum beside it rested 0.3 m in
  // the air. Beside a pit there was no ground below the hall's 0.2 m slab (a drum rolled out of
  // the pit under the hall), and a pit not parented to the hall was covered by its floor.
  const std::string hall = "  - {type: room, name: Hall, length: 10, width: 10, height: 5}\n";
  struct Case {
    std::string objects;
    double rest_z;
  };
  for (const Case& c : {Case{hall + "  - {type: room, name: Mez, parent: Hall, location: [5, 3, 0.3], orientation: [0, 0, 45], "
                                    "length: 2, width: 2, height: 2}\n  - {type: drum, name: D, location: [3.9, 3.4, 0.5], diameter: 0.3, height: 0.4}\n", 0.0},
                        Case{hall + "  - {type: room, name: Mez, parent: Hall, location: [5, 3, 0.3], orientation: [0, 0, 45], "
                                    "length: 2, width: 2, height: 2}\n  - {type: drum, name: D, location: [5, 4.4, 0.5], diameter: 0.3, height: 0.4}\n", 0.3},
                        Case{hall + "  - {type: room, name: Pit, location: [4, 4, -2], length: 2, width: 2, height: 2}\n"
                                    "  - {type: drum, name: D, location: [5, 5, -1.5], diameter: 0.3, height: 0.4}\n", -2.0}}) {
    SCOPED_TRACE(c.objects);
    auto w = world_of(c.objects, "D");
    while (w->time() < 1.5) w->step();
    EXPECT_NEAR(w->pose(d).translation().z(), c.rest_z, 5e-3);
  }
  // Reach: beside the turned mezzanine, into the ground beside a pit (fails), into a pit that is
  // not the hall's child (passes).
  diag = Diagnostics();
  Workcell cell = must_compile("objects:\n" + hall +
                               "  - {type: room, name: Mez, parent: Hall, location: [5, 3, 0.3], orientation: [0, 0, 45], length: 2, width: 2, height: 2}\n"
                               "  - {type: room, name: Pit, location: [6.5, 6.5, -2], length: 2, width: 2, height: 2}\n"
                               "  - {type: arm6, name: R, parent: Hall, location: [6, 7.5, 0]}\n"
                               "constraints:\n  - {name: beside, reach: {device: R, targets: {xyz: [5.4, 6.3, 0.2]}}}\n"
                               "  - {name: pit, reach: {device: R, targets: {xyz: [7.2, 7.5, -0.4]}}}\n"
                               "  - {name: ground, reach: {device: R, targets: {xyz: [6.1, 6.3, -0.4]}}}\n");
  CheckReport rep = check(cell, build_geometry(cell, diag));
  ASSERT_EQ(rep.results.size(), 3u);
  EXPECT_EQ(rep.results[0].status, Status::Pass) << rep.results[0].message;
  EXPECT_EQ(rep.results[1].status, Status::Pass) << rep.results[1].message;
  EXPECT_EQ(rep.results[2].status, Status::Fail);
  EXPECT_NE(rep.results[2].message.find("into the floor of Hall"), std::string::npos) << rep.results[2].message;
  // A pit turned against its hall by 45 deg opens the box around it: warned of.
  diag = Diagnostics();
  Workcell turned = must_compile("objects:\n" + hall + "  - {type: room, name: Pit, parent: Hall, location: [5, 3, -2], orientation: [0, 0, 45], "
                                 "length: 2, width: 2, height: 2}\n");
  build_geometry(turned, diag);
  ASSERT_EQ(diag.warnings().size(), 1u);
  EXPECT_NE(diag.warnings()[0].message.find("'Pit' is turned 45 deg against 'Hall'"), std::string::npos) << diag.warnings()[0].message;
}

TEST_F(Physics, TheFloorIsTheBottomOfTheRoom) {
  auto w = world_of("  - {type: room, name: R, length: 5, width: 5, height: 3, location: [0, 0, 2]}\n"
                    "  - {type: drum, name: D, parent: R, location: [1, 1, 0.3]}\n", "D");
  PhysicsWorld& world = *w;
  EXPECT_NEAR(world.floor_z(), 2.0, 1e-12);
  while (world.time() < 2.0) world.step();
  EXPECT_NEAR(world.pose(d).translation().z(), 2.0, 5e-3);  // dropped 0.3 m onto the room's floor
}

TEST_F(Physics, EveryRoomStandsOnItsOwnFloorAndAPitOpensInIt) {
  // The plane is the bottom of the lowest room (a 2 m pit in the hall); the hall and a mezzanine
  // room have floors of their own (a drum in the hall fell through to the pit's depth).
  const std::string rooms = "  - {type: room, name: Hall, length: 10, width: 10, height: 6}\n"
                            "  - {type: room, name: Pit, parent: Hall, location: [6, 6, -2], length: 2, width: 2, height: 2}\n"
                            "  - {type: room, name: Mezz, parent: Hall, location: [1, 1, 3], length: 3, width: 3, height: 2}\n";
  struct Case {
    const char* drum;
    double rest_z;
  };
  for (const Case& c : {Case{"  - {type: drum, name: D, parent: Hall, location: [3, 7, 0.3]}\n", 0.0},
                        Case{"  - {type: drum, name: D, parent: Pit, location: [1, 1, 2.5]}\n", -2.0},
                        Case{"  - {type: drum, name: D, parent: Mezz, location: [1.5, 1.5, 0.3]}\n", 3.0}}) {
    SCOPED_TRACE(c.drum);
    auto w = world_of(rooms + c.drum, "D");
    EXPECT_NEAR(w->floor_z(), -2.0, 1e-12);
    while (w->time() < 2.5) w->step();
    EXPECT_NEAR(w->pose(d).translation().z(), c.rest_z, 5e-3);
  }
  // Reach keeps a device above the floor of the room it stands in.
  diag = Diagnostics();
  Workcell cell = must_compile("objects:\n" + rooms + "  - {type: arm6, name: R, parent: Mezz, location: [1.5, 1.5, 0]}\n"
                               "constraints:\n  - {name: below, reach: {device: R, targets: {xyz: [3.2, 2.5, 2.7]}}}\n");
  CheckReport rep = check(cell, build_geometry(cell, diag));
  ASSERT_EQ(rep.results.size(), 1u);
  EXPECT_EQ(rep.results[0].status, Status::Fail);
  EXPECT_NE(rep.results[0].message.find("into the floor of Mezz"), std::string::npos) << rep.results[0].message;
  // An arm at the pit's edge reaches down into the pit (it failed: the hall's floor was taken for
  // a plane over the pit), and not into the hall's floor beside it.
  diag = Diagnostics();
  Workcell edge = must_compile("objects:\n" + rooms + "  - {type: arm6, name: R, parent: Hall, location: [5.6, 7, 0]}\n"
                               "constraints:\n  - {name: pit, reach: {device: R, targets: {xyz: [6.9, 7, -0.4]}}}\n"
                               "  - {name: hall, reach: {device: R, targets: {xyz: [4.6, 7, -0.1]}}}\n");
  rep = check(edge, build_geometry(edge, diag));
  ASSERT_EQ(rep.results.size(), 2u);
  EXPECT_EQ(rep.results[0].status, Status::Pass) << rep.results[0].message;
  EXPECT_EQ(rep.results[1].status, Status::Fail);
  EXPECT_NE(rep.results[1].message.find("part link6 goes 0.1 m into the floor of Hall"), std::string::npos) << rep.results[1].message;
}

}  // namespace
}  // namespace sscs::testing

namespace sscs::testing {
namespace {

class Articulated : public VaultTest {
 public:
  std::unique_ptr<PhysicsWorld> world_of(const std::string& objects, const std::string& device, double timestep = 1e-3,
                                         bool fast = false) {
    wc = must_compile("objects:\n" + objects);
    geometry = build_geometry(wc, diag);
    PhysicsOptions physics;
    physics.timestep = timestep;
    physics.fast = fast;
    auto world = std::make_unique<PhysicsWorld>(wc, geometry, physics);
    d = wc.find_object(device);
    model = geometry.objects[d].device.get();
    q0 = world->joints(d);
    world->add_device(d, q0);
    return world;
  }
  /// The plan's joint move from q0 to q1 at the joints' velocity and acceleration limits.
  JointMove move_at_limits(const Eigen::VectorXd& q1) const {
    Eigen::VectorXd v(model->dof()), a(model->dof());
    for (int k = 0; k < model->dof(); ++k) {
      v[k] = model->joint(k).velocity;
      a[k] = model->joint(k).acceleration;
    }
    return JointMove(q0, q1, v, a);
  }
  /// Tool position from the physics bodies against forward kinematics of the measured joints.
  double consistency(const PhysicsWorld& w) {
    Eigen::Isometry3d fk = geometry.objects[d].X_world_object * model->part_poses(w.joints(d))[model->tool_part];
    return (w.part_pose(d, model->tool_part).translation() - fk.translation()).norm();
  }
  Workcell wc;
  GeometryModel geometry;
  const Device* model = nullptr;
  Eigen::VectorXd q0;
  int d = -1;
};

TEST_F(Articulated, MotorsHoldAnArmAgainstGravity) {
  auto w = world_of("  - {type: arm6, name: R}\n", "R");
  Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  while (w->time() < 2.0) {
    w->drive(d, q0, zero);
    w->step();
  }
  EXPECT_LT((w->joints(d) - q0).cwiseAbs().maxCoeff(), 2e-3) << (w->joints(d) - q0).transpose();
  EXPECT_LT(consistency(*w), 1e-3);  // ODE's joint readings and the kinematic model agree
}

TEST_F(Articulated, AUrdfRootedInAWorldLinkStandsStillAndTouchesNothing) {
  // Many vendor URDFs root the robot in a `world` link holding base_link on a fixed joint:
  // base_link is then scenery, like a root part, so it neither sags nor touches the floor it
  // stands on (it was a body, in contact with the floor at depth 0: a collision).
  options.library_dirs = {rx6_dir([](std::string& text) {
    const std::string base = "<link name=\"base_link\">";
    text.replace(text.find(base), base.size(),
                 "<link name=\"world\"/>\n  <joint name=\"world_fixed\" type=\"fixed\"><parent link=\"world\"/>"
                 "<child link=\"base_link\"/></joint>\n  " + base);
  })};
  auto w = world_of("  - {type: rx6, name: R}\n", "R");
  const int base = model->find_part("base_link");
  const Eigen::Isometry3d before = w->part_pose(d, base);
  EXPECT_NEAR(before.translation().z(), 0, 1e-12);  // its cylinder stands on the floor
  Eigen::VectorXd zero = Eigen::VectorXd::Zero(model->dof());
  size_t floor_contacts = 0;
  while (w->time() < 1.0) {
    w->drive(d, q0, zero);
    w->step();
    for (const PhysicsContact& c : w->contacts()) floor_contacts += c.a == -1 || c.b == -1;
  }
  EXPECT_EQ(floor_contacts, 0u);
  EXPECT_TRUE(w->part_pose(d, base).isApprox(before, 1e-12));
  EXPECT_LT(consistency(*w), 1e-3);
}

TEST_F(Articulated, MotorsTrackAPlannedMove) {
  auto w = world_of("  - {type: arm6, name: R}\n", "R");
  Eigen::VectorXd q1 = q0;
  q1[0] += 1.2;   // j1
  q1[1] += 0.4;   // j2 forward
  q1[2] -= 0.3;   // j3
  JointMove move = move_at_limits(q1);
  double worst = 0;
  const double dt = 1e-3;
  while (w->time() < move.duration() + 0.5) {
    double t = w->time() + dt;  // where the joints should be after this step
    w->drive(d, move.position(t), move.velocity(t));
    w->step();
    worst = std::max(worst, (w->joints(d) - move.position(w->time())).cwiseAbs().maxCoeff());
    for (int k = 0; k < 6; ++k) {
      EXPECT_GE(w->joints(d)[k], model->joint(k).lower - 1e-3);
      EXPECT_LE(w->joints(d)[k], model->joint(k).upper + 1e-3);
    }
  }
  EXPECT_LT(worst, 0.01) << "largest tracking error (rad)";
  EXPECT_LT((w->joints(d) - q1).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_LT(consistency(*w), 1e-3);
}

TEST_F(Articulated, MotorsTrackThePlanAtEveryTimestepARunAllowsWithoutWarning) {
  // As a run drives them: each step toward the plan's next position with the step's mean
  // velocity. The correction aimed at the next position, not the current one, and the arm led
  // its plan by 20/s x dt of its motion: a tool 3 cm ahead at 20 ms, a false tracking_error.
  for (double dt : {1e-3, 5e-3, 1e-2}) {
    SCOPED_TRACE(fmt::format("timestep {} s", dt));
    auto w = world_of("  - {type: arm6, name: R}\n", "R", dt);
    Eigen::VectorXd q1 = q0;
    q1[0] += 1.5;
    q1[1] += 0.4;
    q1[5] += 2.0;
    JointMove move = move_at_limits(q1);
    double worst = 0;
    while (w->time() < move.duration() + 0.2) {
      const double t = w->time();
      w->drive(d, move.position(t + dt), (move.position(t + dt) - move.position(t)) / dt);
      w->step();
      worst = std::max(worst, (w->joints(d) - move.position(w->time())).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(worst, 2e-3) << "largest tracking error (rad)";
  }
}

TEST_F(Articulated, ALightFingerOnAHeavyArmStaysWithinItsLimits) {
  // A 2 g finger on a 20 kg arm (and lighter, down to 1 mg) shook in ODE: +-1 cm every 10 ms, a
  // false joint_limit at once, 50 m at 1 mg. Every joint must track its plan within its limits.
  for (const char* finger_mass : {"0.000001", "0.002", "0.02", "0.5", "20"}) {
    SCOPED_TRACE(finger_mass);
    options.library_dirs = {type_dir({{"hand", fmt::format(R"(sscs: 1
type: hand
kind: device
parts:
  - {{name: base, geometry: [{{box: {{size: [0.4, 0.4, 0.2], xyz: [0, 0, 0.1]}}}}]}}
  - name: arm
    parent: base
    joint: {{name: turn, type: revolute, axis: [0, 0, 1], xyz: [0, 0, 0.2], limits: {{min: -180, max: 180, velocity: 90, acceleration: 180}}}}
    geometry: [{{box: {{size: [1.0, 0.15, 0.15], xyz: [0.5, 0, 0.1]}}}}]
    mass: 20
  - name: finger
    parent: arm
    joint: {{name: grip, type: prismatic, axis: [0, 1, 0], xyz: [1.0, 0, 0.1], limits: {{min: 0, max: 0.04, velocity: 0.1, acceleration: 0.5}}}}
    geometry: [{{box: {{size: [0.02, 0.01, 0.06], xyz: [0, 0, -0.03]}}}}]
    mass: {}
tool: {{part: finger}}
)", finger_mass)}})};
    auto w = world_of("  - {type: hand, name: H}\n", "H");
    // Open the finger from its closed limit while turning, close it onto the limit, open again.
    Eigen::VectorXd open = q0;
    open[0] += 1.5;  // turn
    open[1] = 0.03;  // grip
    Eigen::VectorXd closed = open;
    closed[1] = 0;
    Eigen::VectorXd v(2), a(2);
    for (int k = 0; k < 2; ++k) {
      v[k] = model->joint(k).velocity;
      a[k] = model->joint(k).acceleration;
    }
    const std::vector<JointMove> moves = {JointMove(q0, open, v, a), JointMove(open, closed, v, a), JointMove(closed, open, v, a)};
    double worst = 0;
    const double dt = 1e-3;
    for (const JointMove& move : moves) {
      const double start = w->time();
      while (w->time() < start + move.duration() + 0.2) {
        const double t = w->time() + dt - start;  // where the joints should be after this step
        w->drive(d, move.position(t), move.velocity(t));
        w->step();
        const Eigen::VectorXd q = w->joints(d);
        ASSERT_TRUE(q.allFinite());
        worst = std::max(worst, (q - move.position(w->time() - start)).cwiseAbs().maxCoeff());
        for (int k = 0; k < 2; ++k) {
          ASSERT_GE(q[k], model->joint(k).lower - 1e-3) << "t = " << w->time();
          ASSERT_LE(q[k], model->joint(k).upper + 1e-3) << "t = " << w->time();
        }
      }
    }
    EXPECT_LT(worst, 0.01) << "largest tracking error";
    EXPECT_LT(consistency(*w), 1e-3);
  }
}

TEST_F(Articulated, AGraspedDrumMovesWithTheToolAndFallsWhenReleased) {
  // The drum hangs where the tool is at home (its top on the tool), empty: 22 kg.
  wc = must_compile("objects:\n  - {type: arm6, name: R}\n");
  geometry = build_geometry(wc, diag);
  Eigen::Vector3d tool = geometry.objects[0].frame("tool")->translation();
  auto w = world_of(fmt::format("  - {{type: arm6, name: R}}\n  - {{type: drum, name: D, location: [{}, {}, {}]}}\n",
                                tool.x(), tool.y(), tool.z() - 0.851), "R");
  int drum = wc.find_object("D");
  w->grasp(d, drum);
  EXPECT_EQ(w->held(d), drum);
  Eigen::Isometry3d X_tool_drum = w->part_pose(d, model->tool_part).inverse() * w->pose(drum);
  Eigen::VectorXd q1 = q0;
  q1[0] += 1.0;
  JointMove move = move_at_limits(q1);
  double drift = 0;
  while (w->time() < move.duration() + 0.2) {
    double t = w->time() + 1e-3;
    w->drive(d, move.position(t), move.velocity(t));
    w->step();
    Eigen::Isometry3d now = w->part_pose(d, model->tool_part).inverse() * w->pose(drum);
    drift = std::max(drift, (now.translation() - X_tool_drum.translation()).norm());
  }
  EXPECT_LT(drift, 1e-6) << "the drum slipped in the grasp";  // measured: about 2e-9 m
  // Released, it falls freely from where it was.
  double z0 = w->pose(drum).translation().z();
  w->release(d);
  EXPECT_EQ(w->held(d), -1);
  double t0 = w->time();
  while (w->time() < t0 + 0.15) {  // it hangs 0.17 m above the floor: not long enough to land
    w->drive(d, q1, Eigen::VectorXd::Zero(6));
    w->step();
  }
  double t = w->time() - t0;
  EXPECT_NEAR(w->pose(drum).translation().z(), z0 - 9.80665 * t * t / 2, 5e-3);
}

TEST_F(Articulated, AFastRunsRigidLoadIsWhereItsGraspPutsItAtEveryStepOfEveryDevice) {
  // Fast mode's certified clearance takes a held load's poses between two steps from the plan:
  // the tool's pose at q(t) times rigid_load()'s placement. That placement must be where the
  // world puts the load (an offset between the load's body and its object, left out, put a
  // crane's drum 0.43 m off and its bound 5.5 cm under the truth). Every standard device, a drum
  // held at its tool, random moves within the limits.
  std::mt19937_64 rng(20261130);
  for (const std::string& type : standard_devices()) {
    SCOPED_TRACE(type);
    wc = must_compile(fmt::format("objects:\n  - {{type: {}, name: R}}\n", type));
    geometry = build_geometry(wc, diag);
    const Eigen::Vector3d tool = geometry.objects[0].frame("tool")->translation();
    auto w = world_of(fmt::format("  - {{type: {}, name: R}}\n  - {{type: drum, name: D, location: [{}, {}, {}]}}\n", type,
                                  tool.x() + 0.1, tool.y() - 0.05, tool.z() - 0.9),
                      "R", 1e-3, true);
    const int drum = wc.find_object("D");
    w->grasp(d, drum);
    Eigen::Isometry3d X_tool_load;
    ASSERT_EQ(w->rigid_load(d, &X_tool_load), drum);
    const Eigen::Isometry3d X_wo = geometry.objects[d].X_world_object;
    for (int move = 0; move < 3; ++move) {
      Eigen::VectorXd q1 = w->joints(d);
      for (int k = 0; k < model->dof(); ++k) {
        const Joint& j = model->joint(k);
        const double lo = std::isfinite(j.lower) ? j.lower : q1[k] - 1, hi = std::isfinite(j.upper) ? j.upper : q1[k] + 1;
        q1[k] = std::uniform_real_distribution<double>(lo, hi)(rng);
      }
      q0 = w->joints(d);
      const JointMove plan = move_at_limits(q1);
      const double t0 = w->time();
      double worst = 0;
      for (int i = 0; i < 200; ++i) {
        const double t = w->time() + 1e-3 - t0;
        const Eigen::VectorXd q = plan.position(std::min(t, plan.duration()));
        w->drive(d, q, plan.velocity(std::min(t, plan.duration())));
        w->step();
        ASSERT_EQ(w->rigid_load(d, &X_tool_load), drum);
        const Eigen::Isometry3d planned = X_wo * model->part_poses(q)[model->tool_part] * X_tool_load;
        const Eigen::Isometry3d placed = w->pose(drum);
        worst = std::max({worst, (planned.translation() - placed.translation()).norm(),
                          (planned.linear() - placed.linear()).norm()});
      }
      EXPECT_LT(worst, 1e-9) << "move " << move;
    }
  }
}

TEST_F(Articulated, KinematicDevicesFollowThePlanExactly) {
  auto w = world_of("  - {type: agv, name: A}\n", "A");
  Eigen::VectorXd q = q0;
  for (int i = 1; i <= 1000; ++i) {
    q[0] = 0.001 * i;        // 1 m/s along x
    q[2] = 0.0005 * i;       // turning
    w->drive(d, q, Eigen::VectorXd::Zero(3));
    w->step();
  }
  Eigen::Isometry3d fk = geometry.objects[d].X_world_object * model->part_poses(q)[model->find_part("body")];
  Eigen::Isometry3d body = w->part_pose(d, model->find_part("body"));
  EXPECT_LT((body.translation() - fk.translation()).norm(), 1e-9);
  EXPECT_TRUE(body.linear().isApprox(fk.linear(), 1e-9));
}

}  // namespace
}  // namespace sscs::testing
