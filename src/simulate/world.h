#pragma once
/// The physics world of a run: ODE (double precision) with a fixed timestep, the vault's objects
/// as collision geometry (what stands still in a quadtree, what moves in a hash space), a floor, and rigid bodies for objects that move under
/// physics (a drum once it is released). Contacts use friction and restitution (documented in
/// docs/simulation.md).
///
/// Devices are articulated bodies: one rigid body per moving part, ODE hinge, slider and fixed
/// joints with their limits, driven by joint motors (velocity commands with a force limit from
/// the joint's effort), or moved kinematically for `driven: kinematic` devices.
#include <stdexcept>
#include <memory>
#include <vector>

#include <Eigen/Geometry>

#include "compile/workcell.h"
#include "geometry/geometry.h"

struct dxWorld;
struct dxSpace;
struct dxJointGroup;
struct dxJoint;
struct dxGeom;

namespace sscs {

/// ODE reported an error or failed an internal assertion: the run cannot go on.
struct PhysicsFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// An object's mass in a run: what its type declares (`mass:`), else its `mass` attribute when
/// above 0, else its bounds' volume at 500 kg/m^3 (at least 0.1 kg).
double object_mass(const Workcell& wc, const GeometryModel& geometry, int object);

/// The raw ODE objects of a PhysicsWorld: for tools/bench/sim_vs_bare_ode, which steps the same
/// bodies, joints and geoms in a bare loop to measure what sscs adds around ODE.
struct OdeHandles {
  dxWorld* world = nullptr;
  dxJointGroup* contact_group = nullptr;
  /// sscs's collision pass of a step (what moves against itself and against the scenery, through
  /// its near callback: contact filters and surface), called with `collide_data`.
  void (*collide)(void*) = nullptr;
  void* collide_data = nullptr;
  struct Motor {
    dxJoint* joint = nullptr;  ///< null for a device joint without a motor
    bool revolute = true;
    double q_attach = 0;       ///< the joint value ODE measures from
  };
  std::vector<Motor> motors;   ///< the device's, in joint order
};

struct PhysicsOptions {
  double timestep = 1e-3;   ///< s
  bool gravity = true;      ///< -9.80665 m/s^2 along z
  double friction = 0.6;    ///< Coulomb coefficient, every contact (steel on steel or wood, dry)
  double restitution = 0.1; ///< bounce; contacts slower than 0.1 m/s do not bounce
  /// Riders welded to their support while it holds them (PhysicsWorld::ride); off, they stay on
  /// their contacts. On unless SSCS_WELD_RIDERS=0 (the e2e test comparing the two).
  bool weld_riders = true;
  /// Fast mode (campaign-format.md, "Modes"): every device moves kinematically on its plan, a
  /// held load rigidly with its tool (a kinematic body), and a step integrates the dynamics only
  /// when something free moves or is touched by what moves (a release until it rests, a carried
  /// stack's riders, a drum a device pushes); otherwise it only places what moves and finds the
  /// contacts.
  bool fast = false;
};

/// The options of a run with `timestep` and `gravity` (and `fast`), welding as SSCS_WELD_RIDERS says.
PhysicsOptions physics_options(double timestep, bool gravity, bool fast = false);

/// What ODE's solver said during a run ("LCP internal error, s <= 0": on that step it stopped
/// solving the contacts early and left the rest of their forces at zero).
struct SolverMessages {
  size_t count = 0;       ///< steps with a message
  double first_at = 0;    ///< simulated s of the first
  std::string first;      ///< its text
};

struct PhysicsContact {
  int a = -1, b = -1;       ///< objects (a <= b); -1 is the floor; a == b: a device with itself
  int part_a = -1, part_b = -1;  ///< device parts, -1 for other objects
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double depth = 0;
};

class PhysicsWorld {
 public:
  PhysicsWorld(const Workcell& wc, const GeometryModel& geometry, const PhysicsOptions& options);
  ~PhysicsWorld();
  PhysicsWorld(const PhysicsWorld&) = delete;
  PhysicsWorld& operator=(const PhysicsWorld&) = delete;

  /// Makes device `object` articulated, its parts placed at joint values q (the device's joint
  /// vector). Until then a device is static scenery at its instance's values.
  void add_device(int object, const Eigen::VectorXd& q);
  /// Commands the device's joints towards q with velocity qd (feed-forward plus feedback);
  /// kinematic devices are placed at q exactly.
  void drive(int object, const Eigen::VectorXd& q, const Eigen::VectorXd& qd);
  /// The device's joint values now.
  Eigen::VectorXd joints(int object) const;
  /// World pose of a device's part now.
  Eigen::Isometry3d part_pose(int object, int part) const;

  /// Attaches `object` rigidly to the device's tool part (a fixed joint), making it a rigid body
  /// first if it is scenery. The tool's part and the parts it carries do not collide with it.
  void grasp(int device, int object);
  /// Removes the grasp joint: the object is free and falls.
  void release(int device);
  /// The object a device holds, or -1.
  int held(int device) const;

  /// `rider` (a free body) stands on `support` (a load a device carries, or another rider of it).
  /// While it rests there the two are welded: one fixed joint instead of their contacts (up to 8
  /// a geom pair, each 6 rows of the solver: a pallet with four drums on an AGV's deck made the
  /// dense solver cubic in ~200 rows). The weld breaks, the contacts back, on the step where the
  /// patch it stands on could not exert what the weld does (SupportPatch::holds, at kWeldShare of
  /// friction and of the patch: a carrier braking harder than friction holds, a drum tipping over
  /// its rim); it welds again after resting on its support for kWeldAfter. Until `stop_riding`.
  void ride(int rider, int support);
  void stop_riding(int rider);
  /// Whether `rider` is welded to its support now.
  bool welded(int rider) const;
  static constexpr double kWeldShare = 0.7, kWeldAfter = 0.02;  // of friction and the patch; s

  /// Turns a static object into a free rigid body at its current pose, with its mass
  /// (docs/simulation.md says how the mass is found).
  void make_dynamic(int object);
  bool dynamic(int object) const;
  /// A campaign's arriving load is absent until it arrives: its geometry touches nothing.
  void set_present(int object, bool present);
  /// Whether a dynamic object has come to rest (slower than 5 mm/s and 0.01 rad/s for 0.2 s).
  bool at_rest(int object) const;
  /// Advances one timestep: contacts, then the ODE step (in fast mode only when something free
  /// moves or is touched by what moves: see dynamics_steps()).
  void step();
  /// Fast mode: the steps that integrated the dynamics so far (of all steps taken).
  long dynamics_steps() const;
  /// Fast mode: device `object` goes on in physics, as in physics mode, from where it is: its
  /// parts become bodies joined by motors and stops, what it holds is held by a fixed joint. For
  /// what fast mode cannot decide kinematically (a device or its load meeting something: whether
  /// it is stopped, deflected or pushes through is the physics' to say). False when it already is
  /// in physics (or moves kinematically in physics mode too, `driven: kinematic`).
  /// `q_from`, when given: its parts (and what it holds, with its tool) are first set back to
  /// joint values q_from, its pose before the step that met something, so that the physics meets
  /// the obstacle from outside as physics mode does (handed over a step's travel deep into a
  /// plate, a blade went through it where physics mode stopped it).
  bool hand_over(int object, const Eigen::VectorXd* q_from = nullptr);
  /// Fast mode: device `object` moves kinematically on its plan (not handed over): where a step
  /// leaves it is its plan's pose, and what it holds goes rigidly with its tool (`rigid_load`).
  bool on_plan(int object) const;
  /// Fast mode: the load device `object` holds rigidly with its tool (no joint: a kinematic
  /// body), else -1; `X_tool_load`, when given, gets the load object's pose in the tool part's
  /// frame as the grasp placed it (fixed while it holds it).
  int rigid_load(int object, Eigen::Isometry3d* X_tool_load = nullptr) const;
  /// Fast mode: nothing here needs the dynamics now: no device handed over, no stack carried,
  /// every free body at rest. Then the run may glide: place() and advance() instead of steps.
  bool quiet() const;
  /// Fast mode: kinematic device `object` placed at joint values q (and what it holds with it),
  /// at rest.
  void place(int object, const Eigen::VectorXd& q);
  /// Fast mode: `seconds` of simulated time pass with nothing touching anything new (the run
  /// proved it): free bodies stay at rest where they are; no contacts.
  void advance(double seconds);
  double time() const;
  /// ODE's messages of this world's steps so far.
  const SolverMessages& solver_messages() const;
  /// Where the floor is: the plane z = floor_z() (the bottom of the containers, or 0).
  double floor_z() const;

  Eigen::Isometry3d pose(int object) const;
  Eigen::Vector3d velocity(int object) const;
  double mass(int object) const;
  /// Contacts of the last step between distinct objects (or an object and the floor), deepest
  /// point per pair.
  const std::vector<PhysicsContact>& contacts() const;
  /// The force (N) the devices' parts exerted on free object `o` in the last step, and the
  /// device that pushed hardest (-1: none touched it).
  Eigen::Vector3d device_force(int o) const;
  int device_pushing(int o) const;

  /// The ODE world, space and contact group, and the motors of device `object` (if any).
  OdeHandles ode_handles(int object) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sscs
