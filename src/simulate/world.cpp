#include "simulate/world.h"

#include <algorithm>
#include <array>
#include <limits>
#include <vector>
#include <cstdio>
#include <cstring>
#include <cstdarg>
#include <cstdlib>
#include <string_view>
#include <cmath>
#include <map>
#include <deque>
#include <mutex>
#include <numbers>
#include <optional>
#include <set>
#include <tuple>

#include <fmt/format.h>
#include <ode/ode.h>

#include "core/inertia.h"
#include "core/pose.h"
#include "model/device.h"
#include "simulate/support.h"
#include "core/units.h"

namespace sscs {

namespace {

constexpr int kMaxContacts = 8;      // per geom pair and step, after reduction
constexpr int kGatherContacts = 256; // what ODE may report per geom pair and step, before it
constexpr double kDefaultDensity = 500;  // kg/m^3, for objects that state no mass
// A body slower than these for kRestTime is at rest, its velocities averaged over kRestWindow:
// resting contacts jitter from step to step (a drum dropped 0.2 m onto a deck rocked by 1e-5 rad
// at 0.01 rad/s, its mean turn nil, and was never at rest), a body moving for real does not.
constexpr double kRestSpeed = 0.005, kRestTurn = 0.01, kRestTime = 0.2;  // m/s, rad/s, s
constexpr double kRestWindow = 0.02;                                      // s
// Rolling and spinning resistance (m: the torque is at most this times the normal force): a
// drum landed tilted spun and wobbled on its rim for ever (5 deg/s, never at rest), for ODE's
// point contacts have no torsion of a contact patch. Steel on concrete rolls with about 1 mm.
// One value about every axis: ODE reads rho2 and rhoN only with dContactAxisDep, which sscs
// does not set (a 1 cm spin resistance stated here and in the docs was never applied).
constexpr double kRollingResistance = 0.001;
constexpr double kMaxCorrectingVel = 1.0;  // m/s: how fast a contact may push bodies apart to undo a penetration
constexpr double kStopMargin = 2e-3;    // rad or m: joint stops lie this far beyond the limits

/// ODE's messages (not its errors): "LCP internal error" when a step's solver gives up on a
/// contact, printed for every step (592 lines for a 1 mg drum in a gripper). Counted per world
/// (the one stepping on this thread) and said once a run on stderr, with the simulated time.
thread_local SolverMessages* g_messages = nullptr;
thread_local double g_message_time = 0;
void ode_message(int num, const char* msg, va_list ap) {
  char text[512];
  std::vsnprintf(text, sizeof text, msg, ap);
  if (g_messages && g_messages->count++ > 0) return;
  if (g_messages) {
    g_messages->first_at = g_message_time;
    g_messages->first = fmt::format("ODE message {}: {}", num, text);
  }
  const bool solver = std::strstr(text, "LCP") != nullptr;
  std::fprintf(stderr, "warning: at %.3f s: ODE message %d: %s (%sthe run's summary.json counts them)\n", g_message_time, num, text,
               solver ? "the physics solver stopped early on a step's contacts, leaving their remaining forces at zero; " : "");
}

/// ODE's errors and internal assertions ("d != 0" in its cylinder collider) abort the process:
/// a run died with exit 134 and left its staging folder. They become a PhysicsFailure the run
/// reports as an internal error (exit 3), its staging folder removed.
[[noreturn]] void ode_failure(int num, const char* msg, va_list ap) {
  char text[1024];
  std::vsnprintf(text, sizeof text, msg, ap);
  throw PhysicsFailure(fmt::format("the physics engine (ODE) failed: error {}: {}", num, text));
}

void init_ode() {
  static std::once_flag once;
  std::call_once(once, [] {
    dInitODE2(0);
    dSetMessageHandler(ode_message);
    dSetErrorHandler(ode_failure);
    dSetDebugHandler(ode_failure);
  });
}

void to_ode(const Eigen::Matrix3d& R, dMatrix3 out) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out[r * 4 + c] = R(r, c);
    out[r * 4 + 3] = 0;
  }
}

Eigen::Isometry3d from_ode(const dReal* p, const dReal* R) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    X.translation()[r] = p[r];
    for (int c = 0; c < 3; ++c) X.linear()(r, c) = R[r * 4 + c];
  }
  return X;
}

/// Keeps `keep` of the `n` contacts of one geom pair, spread over the contact area: the deepest,
/// then each time the one farthest from those kept. ODE fills the contacts of a mesh pair in
/// triangle order and stops at the count it is given, so the first 8 of a drum's 48-vertex rim
/// all lay on one side: the drum rocked, walked 3 cm in 20 s and never came to rest, on a
/// pallet it turned 54° and hopped. A spread subset holds it still (tests/unit/physics_test.cpp).
/// Contacts of two cylinders on one axis (drums stacked), which ODE's cylinder collider
/// aborts on ("d != 0" in collideCylCyl: a run with a drum on a drum died, exit 134): where
/// their end faces overlap, 8 points on the smaller rim at the middle of the overlap, the
/// normal along the axis from g2 to g1 (ODE's convention). -1 when they are not coaxial
/// (ODE's collider handles them), 0 when apart.
int coaxial_cylinders(dGeomID g1, dGeomID g2, dContactGeom* out) {
  if (dGeomGetClass(g1) != dCylinderClass || dGeomGetClass(g2) != dCylinderClass) return -1;
  const dReal *R1 = dGeomGetRotation(g1), *R2 = dGeomGetRotation(g2), *p1 = dGeomGetPosition(g1), *p2 = dGeomGetPosition(g2);
  const Eigen::Vector3d a1(R1[2], R1[6], R1[10]), a2(R2[2], R2[6], R2[10]);
  const Eigen::Vector3d c1(p1[0], p1[1], p1[2]), c2(p2[0], p2[1], p2[2]);
  const Eigen::Vector3d between = c1 - c2;
  if (std::abs(a1.dot(a2)) < 1 - 1e-12 || (between - between.dot(a1) * a1).norm() > 1e-6) return -1;
  dReal r1, l1, r2, l2;
  dGeomCylinderGetParams(g1, &r1, &l1);
  dGeomCylinderGetParams(g2, &r2, &l2);
  const double along = between.dot(a1);  // g1's centre from g2's, along the axis
  const double depth = (l1 + l2) / 2 - std::abs(along);
  if (depth < 0) return 0;
  const Eigen::Vector3d normal = along >= 0 ? a1 : Eigen::Vector3d(-a1);  // from g2 into g1
  const Eigen::Vector3d middle = c2 + normal * (l2 / 2 - depth / 2);
  const Eigen::Vector3d u = a1.unitOrthogonal(), v = a1.cross(u);
  const double r = std::min(r1, r2);
  for (int k = 0; k < 8; ++k) {
    const double angle = k * std::numbers::pi / 4;
    const Eigen::Vector3d at = middle + r * (std::cos(angle) * u + std::sin(angle) * v);
    dContactGeom& c = out[k];
    c = dContactGeom{};
    for (int i = 0; i < 3; ++i) {
      c.pos[i] = at[i];
      c.normal[i] = normal[i];
    }
    c.depth = depth;
    c.g1 = g1;
    c.g2 = g2;
  }
  return 8;
}

int spread_contacts(dContactGeom* c, int n, int keep) {
  if (n <= keep) return n;
  int deepest = 0;
  for (int i = 1; i < n; ++i)
    if (c[i].depth > c[deepest].depth) deepest = i;
  std::swap(c[0], c[deepest]);
  std::vector<double> d2(n, std::numeric_limits<double>::infinity());  // squared distance to the kept
  for (int m = 1; m < keep; ++m) {
    int far = m;
    for (int i = m; i < n; ++i) {
      const double dx = c[i].pos[0] - c[m - 1].pos[0], dy = c[i].pos[1] - c[m - 1].pos[1], dz = c[i].pos[2] - c[m - 1].pos[2];
      d2[i] = std::min(d2[i], dx * dx + dy * dy + dz * dz);
      if (d2[i] > d2[far]) far = i;
    }
    std::swap(c[m], c[far]);
    std::swap(d2[m], d2[far]);
  }
  return keep;
}

}  // namespace

PhysicsOptions physics_options(double timestep, bool gravity, bool fast) {
  PhysicsOptions o;
  o.timestep = timestep;
  o.gravity = gravity;
  o.fast = fast;
  const char* weld = std::getenv("SSCS_WELD_RIDERS");
  o.weld_riders = !(weld && std::string_view(weld) == "0");
  return o;
}

double object_mass(const Workcell& wc, const GeometryModel& geometry, int o) {
  if (double m = geometry.objects[o].declared_mass; m > 0) return m;
  const Object& obj = wc.objects[o];
  if (int a = wc.types[obj.type].find_attribute("mass"); a >= 0 && wc.values[obj.first_slot + kFirstAttributeSlot + a] > 0)
    return wc.values[obj.first_slot + kFirstAttributeSlot + a];
  Eigen::Vector3d size = geometry.objects[o].bbox_world.sizes();
  return std::max(kDefaultDensity * size.prod(), 0.1);
}

/// What a geom belongs to: an object (-1: the floor) and, for devices, a part.
struct GeomTag {
  int object = -1;
  int part = -1;
};

struct DeviceBodies {
  std::vector<dBodyID> bodies;                 // per part; null for the root (static)
  std::vector<Eigen::Isometry3d> X_body_part;  // the part's frame in its body's
  struct JointRec {
    dJointID joint = nullptr;
    JointType type = JointType::Fixed;
    double q_attach = 0;  // the joint value when attached (ODE measures from there)
    // ODE reports hinge angles in (-pi, pi]: unwrapped after every step into a continuous value.
    double raw = 0, unwrapped = 0;
  };
  std::vector<JointRec> joints;  // per device joint (joint vector order)
  bool kinematic = false;
  Eigen::VectorXd commanded;     // kinematic devices: where they were last placed
  std::vector<Eigen::Isometry3d> target;  // kinematic devices: each body's pose at `commanded`
};

struct PhysicsWorld::Impl {
  const Workcell& wc;
  const GeometryModel& geometry;
  PhysicsOptions options;
  dWorldID world = nullptr;
  /// What has a body (device parts, free objects) in a hash space, collided with itself and each
  /// of its geoms with the scenery: everything else, standing still, in a quadtree (x, y) that
  /// is never rebuilt. One space of both hashed the 143 drums of the reference store at every
  /// step, 70 % of its run.
  dSpaceID space = nullptr, scenery = nullptr;
  dJointGroupID contact_group = nullptr;
  double floor = 0;
  double time = 0;
  SolverMessages messages;
  std::vector<std::vector<dGeomID>> geoms;  // per object
  std::vector<dBodyID> bodies;              // per object; null when static
  std::vector<Eigen::Isometry3d> X_body_object;
  std::vector<double> masses;
  bool broken = false;  // ODE failed inside a step: its state is not to be touched again
  std::vector<double> still_for;  // per object: how long its body has been slower than the rest thresholds (s)
  /// Per object: its body's last velocities (linear, angular), kRestWindow of them, oldest overwritten.
  struct Velocities {
    std::vector<Eigen::Matrix<double, 6, 1>> samples;
    size_t next = 0;
  };
  std::vector<Velocities> recent;
  /// Per object: what its body touched at the last step ((object, part), sorted).
  std::vector<std::vector<std::pair<int, int>>> touching, touching_next;

  void sum_device_forces() {
    if (feedback_of.empty() && !pushed_last_step) return;  // the common step: no device touches a free body
    pushed_last_step = !feedback_of.empty();
    std::fill(device_force.begin(), device_force.end(), Eigen::Vector3d::Zero());
    std::fill(device_pushing.begin(), device_pushing.end(), -1);
    std::map<std::pair<int, int>, Eigen::Vector3d> by_device;
    for (size_t k = 0; k < feedback_of.size(); ++k) {
      const dReal* f = feedback_of[k].first ? feedback[k].f1 : feedback[k].f2;
      auto [it, fresh] = by_device.try_emplace({feedback_of[k].object, feedback_of[k].device}, Eigen::Vector3d::Zero());
      it->second += Eigen::Vector3d(f[0], f[1], f[2]);
    }
    std::vector<double> largest(device_force.size(), 0);
    for (const auto& [key, F] : by_device) {
      device_force[key.first] += F;
      if (F.norm() > largest[key.first]) {
        largest[key.first] = F.norm();
        device_pushing[key.first] = key.second;
      }
    }
    feedback.clear();
    feedback_of.clear();
  }

  /// A body ODE has put to sleep stays asleep when what held it goes away (a drum set down on
  /// its rim, leaning on the gripper's fingers, froze 3.5 deg past tipping when they drew back,
  /// and the run said ok; it had lain still long enough while they touched it): one that loses
  /// a contact it had is woken, with ODE's idle time started anew, so gravity acts on it.
  void wake_unsupported() {
    std::vector<std::vector<std::pair<int, int>>>& now = touching_next;  // reused: no allocation a step
    now.resize(bodies.size());
    for (auto& partners : now) partners.clear();
    for (const PhysicsContact& c : contacts) {
      if (c.a >= 0 && bodies[c.a]) now[c.a].emplace_back(c.b, c.part_b);
      if (c.b >= 0 && bodies[c.b]) now[c.b].emplace_back(c.a, c.part_a);
    }
    for (size_t o = 0; o < bodies.size(); ++o) {
      std::sort(now[o].begin(), now[o].end());
      if (!bodies[o]) continue;
      if (asleep(bodies[o])) {  // its contacts are not looked for (collide): it touches what it did
        now[o] = touching[o];
        continue;
      }
      for (const auto& partner : touching[o])
        if (!std::binary_search(now[o].begin(), now[o].end(), partner)) {
          dBodyEnable(bodies[o]);  // also restarts its idle time
          // Fast mode: what a device (its part, its load) let go of moves again until it rests
          // (it is not stepped while at rest); contacts flickering on scenery do not count.
          const auto [other, part] = partner;
          if (options.fast && (part >= 0 || (other >= 0 && bodies[other] && dBodyIsKinematic(bodies[other])))) still_for[o] = 0;
          break;
        }
    }
    touching.swap(now);
  }
  size_t rest_samples = 1;  // velocities averaged for rest: kRestWindow of steps
  std::vector<dTriMeshDataID> meshes;
  std::vector<std::vector<double>> mesh_vertices;
  std::vector<std::vector<int>> mesh_indices;
  std::vector<PhysicsContact> contacts;
  /// This step's contact forces of device parts on free bodies (ODE fills them in the step).
  struct Pushed {
    int object = -1, device = -1;
    bool first = false;  ///< the object is the joint's first body
  };
  std::deque<dJointFeedback> feedback;
  std::vector<Pushed> feedback_of;
  std::vector<Eigen::Vector3d> device_force;  ///< per object: the force devices' parts exerted on it in the last step
  std::vector<int> device_pushing;            ///< per object: the device whose parts pushed hardest, or -1
  bool pushed_last_step = false;
  std::map<std::tuple<int, int, int, int>, size_t> contact_index;
  std::deque<GeomTag> tags;
  std::map<int, DeviceBodies> devices;
  struct Grip {
    int object = -1;
    dJointID joint = nullptr;      // none in fast mode: the load is a kinematic body
    std::vector<char> tool_parts;  // the tool's part and the parts it carries
    Eigen::Isometry3d X_tool_load = Eigen::Isometry3d::Identity();  // fast mode: the load's body in the tool's
    Eigen::Isometry3d target = Eigen::Isometry3d::Identity();       // fast mode: where the load's body goes
  };
  std::map<int, Grip> grips;  // by device
  /// A rider and what it stands on (PhysicsWorld::ride): welded while at rest there.
  struct Ride {
    int support = -1;
    dJointID weld = nullptr;
    dJointFeedback feedback{};      ///< the weld's force and torque on the rider, last step
    std::optional<SupportPatch> patch;  ///< what it stands on, in its frame, when welded
    double still_for = 0;           ///< how long it has rested on its support (s)
    std::vector<Eigen::Vector3d> points, normals;  ///< this step's contacts with the support (normals into the rider)
  };
  std::map<int, Ride> rides;  // by rider

  /// A contact of the solver between a rider and its support, not welded: its patch for a weld.
  void note_support(int o1, int o2, const dContactGeom* c, int n) {
    for (auto [rider, other, sign] : {std::tuple{o1, o2, 1.0}, std::tuple{o2, o1, -1.0}}) {
      auto it = rider >= 0 ? rides.find(rider) : rides.end();
      if (it == rides.end() || it->second.support != other || it->second.weld) continue;
      for (int i = 0; i < n; ++i) {
        it->second.points.emplace_back(c[i].pos[0], c[i].pos[1], c[i].pos[2]);
        it->second.normals.push_back(sign * Eigen::Vector3d(c[i].normal[0], c[i].normal[1], c[i].normal[2]));
      }
    }
  }

  void unweld(Ride& r, int rider) {
    if (!r.weld) return;
    dJointDestroy(r.weld);
    r.weld = nullptr;
    r.patch.reset();
    r.still_for = 0;
    dBodyEnable(bodies[rider]);
  }

  /// After a step: a weld the patch could not hold breaks; a rider resting on its support for
  /// kWeldAfter, on a patch that holds it, is welded.
  void update_rides() {
    for (auto& [rider, r] : rides) {
      dBodyID b = bodies[rider], s = r.support >= 0 ? bodies[r.support] : nullptr;
      const Eigen::Isometry3d X_world_rider = from_ode(dBodyGetPosition(b), dBodyGetRotation(b));
      if (r.weld) {
        const Eigen::Vector3d f(r.feedback.f1[0], r.feedback.f1[1], r.feedback.f1[2]);
        const Eigen::Vector3d tau(r.feedback.t1[0], r.feedback.t1[1], r.feedback.t1[2]);
        if (!r.patch->holds(f, tau, X_world_rider.translation(), X_world_rider, options.friction, PhysicsWorld::kWeldShare))
          unweld(r, rider);
        continue;
      }
      // At rest on the support: the rider's velocity is the support's at the rider's centre.
      const Eigen::Vector3d p(dBodyGetPosition(b)), ps(dBodyGetPosition(s));
      const Eigen::Vector3d w_s(dBodyGetAngularVel(s)), v_s = Eigen::Vector3d(dBodyGetLinearVel(s)) + w_s.cross(p - ps);
      const bool resting = (Eigen::Vector3d(dBodyGetLinearVel(b)) - v_s).norm() < kRestSpeed &&
                           (Eigen::Vector3d(dBodyGetAngularVel(b)) - w_s).norm() < kRestTurn && !r.points.empty();
      r.still_for = resting ? r.still_for + options.timestep : 0;
      if (r.still_for >= PhysicsWorld::kWeldAfter - 1e-9) {
        r.patch = SupportPatch::from_contacts(r.points, r.normals, X_world_rider);
        if (r.patch) {
          r.weld = dJointCreateFixed(world, nullptr);
          dJointAttach(r.weld, b, s);
          dJointSetFixed(r.weld);
          dJointSetFeedback(r.weld, &r.feedback);
        }
      }
    }
  }
  std::vector<char> zone;     // per object: a keep-out volume (no solid: only entering it is recorded)

  bool held_by_a_device(int object) const {
    for (const auto& [device, grip] : grips)
      if (grip.object == object) return true;
    return false;
  }

  /// Whether a contact between these is the grip itself (the gripper on what it holds).
  bool gripping(const GeomTag& a, const GeomTag& b) const {
    for (const auto& [device, grip] : grips)
      for (auto [x, y] : {std::pair{&a, &b}, std::pair{&b, &a}})
        if (x->object == device && y->object == grip.object && x->part >= 0 &&
            x->part < static_cast<int>(grip.tool_parts.size()) && grip.tool_parts[x->part])
          return true;
    return false;
  }

  void tag(dGeomID g, int object, int part) {
    tags.push_back({object, part});
    dGeomSetData(g, &tags.back());
  }

  /// Places geom `g` at world pose X (static, or as an offset on its body).
  static void place(dGeomID g, const Eigen::Isometry3d& X) {
    dMatrix3 R;
    to_ode(X.linear(), R);
    if (dGeomGetBody(g)) {
      dGeomSetOffsetWorldPosition(g, X.translation().x(), X.translation().y(), X.translation().z());
      dGeomSetOffsetWorldRotation(g, R);
    } else {
      dGeomSetPosition(g, X.translation().x(), X.translation().y(), X.translation().z());
      dGeomSetRotation(g, R);
    }
  }

  Impl(const Workcell& w, const GeometryModel& g, const PhysicsOptions& o) : wc(w), geometry(g), options(o) {}

  dGeomID make_geom(const Shape& s) {
    switch (s.kind) {
      case Shape::Kind::Box: return dCreateBox(nullptr, s.box_size.x(), s.box_size.y(), s.box_size.z());
      case Shape::Kind::Cylinder: return dCreateCylinder(nullptr, s.radius, s.length);
      case Shape::Kind::Sphere: return dCreateSphere(nullptr, s.radius);
      case Shape::Kind::Mesh: {
        auto& v = mesh_vertices.emplace_back();
        for (const Eigen::Vector3d& p : s.mesh->vertices)
          for (int k = 0; k < 3; ++k) v.push_back(p[k] * s.scale[k]);
        auto& idx = mesh_indices.emplace_back();
        for (const Eigen::Vector3i& t : s.mesh->triangles)
          for (int k = 0; k < 3; ++k) idx.push_back(t[k]);
        dTriMeshDataID data = dGeomTriMeshDataCreate();
        dGeomTriMeshDataBuildDouble(data, v.data(), 3 * sizeof(double), static_cast<int>(v.size() / 3), idx.data(),
                                    static_cast<int>(idx.size()), 3 * sizeof(int));
        meshes.push_back(data);
        return dCreateTriMesh(nullptr, data, nullptr, nullptr, nullptr);
      }
    }
    return nullptr;
  }

  /// A device's parts joined by ODE hinges, sliders and fixed joints with motors and stops, the
  /// parts standing at joint values q.
  void join_parts(int o, DeviceBodies& db, const Eigen::VectorXd& q) {
    const ObjectGeometry& g = geometry.objects[o];
    const Device& d = *g.device;
    std::vector<Eigen::Isometry3d> X = d.part_poses(q);
    for (auto& x : X) x = g.X_world_object * x;
    const std::vector<char> moved = d.moved_parts();
    for (size_t p = 0; p < d.parts.size(); ++p) {
      const Part& part = d.parts[p];
      if (!moved[p]) continue;
      const Joint& j = part.joint;
      dBodyID child = db.bodies[p], parent = db.bodies[part.parent];  // null parent: the world
      Eigen::Isometry3d X_joint = X[part.parent] * j.origin;
      Eigen::Vector3d anchor = X_joint.translation(), axis = X_joint.linear() * j.axis;
      dJointID joint = nullptr;
      switch (j.type) {
        case JointType::Revolute:
          joint = dJointCreateHinge(world, nullptr);
          dJointAttach(joint, child, parent);
          dJointSetHingeAnchor(joint, anchor.x(), anchor.y(), anchor.z());
          dJointSetHingeAxis(joint, axis.x(), axis.y(), axis.z());
          break;
        case JointType::Prismatic:
          joint = dJointCreateSlider(world, nullptr);
          dJointAttach(joint, child, parent);
          dJointSetSliderAxis(joint, axis.x(), axis.y(), axis.z());
          break;
        case JointType::Fixed:
          joint = dJointCreateFixed(world, nullptr);
          dJointAttach(joint, child, parent);
          dJointSetFixed(joint);
          break;
      }
      if (j.q < 0) continue;
      double q0 = q[j.q];
      db.joints[j.q] = {joint, j.type, q0};
      double fmax = j.effort > 0 ? j.effort : 1e5;
      bool hinge = j.type == JointType::Revolute;
      auto set = [&](int param, double v) {
        if (hinge) dJointSetHingeParam(joint, param, v);
        else dJointSetSliderParam(joint, param, v);
      };
      set(dParamFMax, fmax);
      set(dParamVel, 0);
      // Stops, measured from the attach value, kStopMargin beyond the limits: a motor powered away
      // from a stop it rests on gets its whole force for a step (ODE's "fudge factor" case), and a
      // joint planned to its limit (a gripper's closed finger) jumped: 1e5 N on a 2 g finger threw
      // it 50 m. Within the limits the motor alone holds the plan. ODE's hinge stops must lie within
      // +-pi.
      double lo = j.lower - kStopMargin - q0, hi = j.upper + kStopMargin - q0;
      if (std::isfinite(lo) && std::isfinite(hi) && (!hinge || (lo >= -3.14159 && hi <= 3.14159))) {
        set(dParamLoStop, lo);
        set(dParamHiStop, hi);
      }
    }
  }

  static void near_callback(void* data, dGeomID g1, dGeomID g2) { static_cast<Impl*>(data)->near(g1, g2); }

  /// A kinematic body given the velocities that take it to `X` in `dt` (ODE's step integrates
  /// them; contacts with it see them).
  static void aim(dBodyID b, const Eigen::Isometry3d& X, double dt) {
    const dReal* old = dBodyGetPosition(b);
    dBodySetLinearVel(b, (X.translation().x() - old[0]) / dt, (X.translation().y() - old[1]) / dt, (X.translation().z() - old[2]) / dt);
    Eigen::AngleAxisd turn(X.linear() * from_ode(old, dBodyGetRotation(b)).linear().transpose());
    Eigen::Vector3d wv = turn.axis() * turn.angle() / dt;
    dBodySetAngularVel(b, wv.x(), wv.y(), wv.z());
  }
  static void place_body(dBodyID b, const Eigen::Isometry3d& X) {
    dBodySetPosition(b, X.translation().x(), X.translation().y(), X.translation().z());
    dMatrix3 R;
    to_ode(X.linear(), R);
    dBodySetRotation(b, R);
  }

  /// Fast mode: kinematic devices and held loads exactly where they were aimed (ODE's
  /// integration of their velocities, or none when the step skipped the dynamics).
  void place_kinematic() {
    for (auto& [o, db] : devices)
      if (db.kinematic)
        for (size_t p = 0; p < db.bodies.size() && p < db.target.size(); ++p)
          if (db.bodies[p]) place_body(db.bodies[p], db.target[p]);
    for (auto& [device, grip] : grips)
      if (!grip.joint && bodies[grip.object]) place_body(bodies[grip.object], grip.target);
  }

  /// Fast mode: whether this step's dynamics decide something: a free body (not kinematic) that
  /// is not at rest, or one that what moves (a kinematic part or load) touches or carries; those
  /// are woken (ODE wakes no body for a kinematic one: riders asleep on a pallet the tool lifted
  /// stayed in the air).
  bool dynamics_needed() {
    // Whatever else makes the step run, what moves wakes what it touches or carries (below).
    bool needed = !handed.empty();
    for (size_t o = 0; o < bodies.size() && !needed; ++o)
      if (bodies[o] && !dBodyIsKinematic(bodies[o]) && dBodyIsEnabled(bodies[o]) && still_for[o] < kRestTime - 1e-9) needed = true;
    auto free = [&](int o, int part) { return o >= 0 && part < 0 && bodies[o] && !dBodyIsKinematic(bodies[o]); };
    // A kinematic body that moves this step: a device's part or a held load.
    auto moves = [](dBodyID b) {
      return b && dBodyIsKinematic(b) &&
             (Eigen::Vector3d(dBodyGetLinearVel(b)).squaredNorm() > 0 || Eigen::Vector3d(dBodyGetAngularVel(b)).squaredNorm() > 0);
    };
    auto moving = [&](int o, int part) {
      if (o >= 0 && part >= 0) {
        auto it = devices.find(o);
        return it != devices.end() && static_cast<size_t>(part) < it->second.bodies.size() && moves(it->second.bodies[part]);
      }
      return o >= 0 && moves(bodies[o]);
    };
    for (const PhysicsContact& c : contacts)
      for (auto [x, part_x, y, part_y] : {std::tuple{c.a, c.part_a, c.b, c.part_b}, std::tuple{c.b, c.part_b, c.a, c.part_a}})
        if (free(x, part_x) && moving(y, part_y)) {
          dBodyEnable(bodies[x]);
          needed = true;
        }
    // A stack on a load that moves (its riders welded to it touch it through no contact).
    for (const auto& [rider, r] : rides)
      if (r.support >= 0 && moves(bodies[r.support])) {
        dBodyEnable(bodies[rider]);
        needed = true;
      }
    return needed;
  }
  long dynamics_steps = 0;
  std::set<int> handed;  // fast mode: devices handed over to physics

  /// The step's collision pass: what moves against what moves, then each of its geoms against
  /// the scenery's quadtree (only the blocks its box overlaps).
  /// Fast mode: a free body asleep where it came to rest (step()) is scenery again until
  /// something that moves touches it (ODE wakes a body a contact joins to an awake one, and
  /// dynamics_needed() one that a kinematic part or load touches): its contacts with the scenery
  /// and with other sleepers are not looked for (a store's racked drums on their beams, each step).
  /// Whether free body `o` touched a device's part or a held load at this step's contacts.
  bool touches_device(size_t o) const {
    for (const auto& [other, part] : touching[o])
      if (part >= 0 || (other >= 0 && bodies[other] && dBodyIsKinematic(bodies[other]))) return true;
    return false;
  }
  bool asleep(dBodyID b) const { return options.fast && b && !dBodyIsEnabled(b) && !dBodyIsKinematic(b); }
  static void collide(void* data) {
    Impl& w = *static_cast<Impl*>(data);
    dSpaceCollide(w.space, &w, &near_callback);
    for (int i = 0, n = dSpaceGetNumGeoms(w.space); i < n; ++i) {
      dGeomID g = dSpaceGetGeom(w.space, i);
      if (!w.asleep(dGeomGetBody(g))) dSpaceCollide2(g, reinterpret_cast<dGeomID>(w.scenery), &w, &near_callback);
    }
  }
  /// A new geom into the scenery, or among what moves when it has a body.
  void add_geom(dGeomID g) { dSpaceAdd(dGeomGetBody(g) ? space : scenery, g); }

  void near(dGeomID g1, dGeomID g2) {
    dBodyID b1 = dGeomGetBody(g1), b2 = dGeomGetBody(g2);
    if ((!b1 || asleep(b1)) && (!b2 || asleep(b2))) return;  // scenery does not collide with scenery
    if (b1 == b2) return;
    const GeomTag& t1 = *static_cast<const GeomTag*>(dGeomGetData(g1));
    const GeomTag& t2 = *static_cast<const GeomTag*>(dGeomGetData(g2));
    if (t1.object == t2.object) {
      // One object: only a device's non-adjacent parts meet (self-collision).
      const ObjectGeometry& g = geometry.objects[t1.object];
      if (!g.device || t1.part == t2.part || g.device->may_touch(t1.part, t2.part)) return;
    }
    if (b1 && b2 && dAreConnectedExcluding(b1, b2, dJointTypeContact)) return;  // joined parts
    if (gripping(t1, t2)) return;
    int o1 = t1.object, o2 = t2.object;
    // A keep-out zone meets only a device's parts and what a device holds (a drum falling through
    // one is no event), and pushes nothing: the contact is recorded, no joint made.
    const bool in_zone = (o1 >= 0 && zone[o1]) || (o2 >= 0 && zone[o2]);
    if (in_zone) {
      const GeomTag& other = o1 >= 0 && zone[o1] ? t2 : t1;
      if (other.object < 0 || (other.part < 0 && !held_by_a_device(other.object))) return;
    }
    thread_local std::array<dContactGeom, kGatherContacts> found;
    int all = coaxial_cylinders(g1, g2, found.data());
    if (all < 0) all = dCollide(g1, g2, kGatherContacts, found.data(), sizeof(dContactGeom));
    // The deepest point of the pair is recorded from all contacts, the solver gets a spread few.
    double deepest = -1;
    Eigen::Vector3d deepest_at = Eigen::Vector3d::Zero();
    for (int i = 0; i < all; ++i)
      if (found[i].depth > deepest) {
        deepest = found[i].depth;
        deepest_at = {found[i].pos[0], found[i].pos[1], found[i].pos[2]};
      }
    // Neither side can move (a kinematic device's part against scenery or another kinematic
    // part): a contact joint between them would be a row of the solver with no mass behind it,
    // held only by its softness. The contact is recorded (a collision), no joint made.
    const bool movable = (b1 && !dBodyIsKinematic(b1)) || (b2 && !dBodyIsKinematic(b2));
    const int n = in_zone || !movable ? 0 : spread_contacts(found.data(), all, kMaxContacts);
    if (!rides.empty() && n > 0) note_support(t1.object, t2.object, found.data(), n);
    // A device's part against a free body (not one it holds: that is no contact).
    int pushed = -1, pusher = -1;
    if (t1.part >= 0 && t2.part < 0 && b2) pushed = o2, pusher = o1;
    if (t2.part >= 0 && t1.part < 0 && b1) pushed = o1, pusher = o2;
    for (int i = 0; i < n; ++i) {
      dContact c{};
      c.geom = found[i];
      c.surface.mode = dContactBounce | dContactSoftCFM | dContactApprox1 | dContactRolling;
      c.surface.rho = kRollingResistance;
      c.surface.mu = options.friction;
      c.surface.bounce = options.restitution;
      c.surface.bounce_vel = 0.1;
      c.surface.soft_cfm = 1e-6;
      dJointID j = dJointCreateContact(world, contact_group, &c);
      dJointAttach(j, b1, b2);
      if (pushed >= 0) {  // what a device's part does to a free body: measured by the step
        feedback.emplace_back();
        dJointSetFeedback(j, &feedback.back());
        feedback_of.push_back({pushed, pusher, pushed == o1});
      }
    }
    if (all == 0) return;
    bool swap = std::make_pair(o1, t1.part) > std::make_pair(o2, t2.part);
    const GeomTag& a = swap ? t2 : t1;
    const GeomTag& b = swap ? t1 : t2;
    auto [it, fresh] = contact_index.try_emplace({a.object, a.part, b.object, b.part}, contacts.size());
    if (fresh) contacts.push_back({a.object, b.object, a.part, b.part, Eigen::Vector3d::Zero(), -1});
    PhysicsContact& pc = contacts[it->second];
    if (deepest > pc.depth) {
      pc.depth = deepest;
      pc.point = deepest_at;
    }
  }
};

PhysicsWorld::PhysicsWorld(const Workcell& wc, const GeometryModel& geometry, const PhysicsOptions& options)
    : impl_(std::make_unique<Impl>(wc, geometry, options)) {
  init_ode();
  Impl& w = *impl_;
  w.world = dWorldCreate();
  dWorldSetGravity(w.world, 0, 0, options.gravity ? -kStandardGravity : 0);
  dWorldSetERP(w.world, 0.2);
  dWorldSetCFM(w.world, 1e-9);
  dWorldSetContactMaxCorrectingVel(w.world, kMaxCorrectingVel);
  // A body slower than 5 mm/s and 0.01 rad/s for 0.2 s is at rest: ODE stops integrating it
  // (which also ends the contact jitter of meshes) until something touches or moves it.
  dWorldSetAutoDisableFlag(w.world, 1);
  dWorldSetAutoDisableLinearThreshold(w.world, kRestSpeed);
  dWorldSetAutoDisableAngularThreshold(w.world, kRestTurn);
  dWorldSetAutoDisableTime(w.world, kRestTime);
  dWorldSetAutoDisableSteps(w.world, 0);
  w.rest_samples = static_cast<size_t>(std::max(1L, std::lround(kRestWindow / options.timestep)));
  dWorldSetAutoDisableAverageSamplesCount(w.world, static_cast<unsigned>(w.rest_samples));
  w.space = dHashSpaceCreate(nullptr);
  dHashSpaceSetLevels(w.space, -4, 6);  // cells from 6 cm to 64 m
  {
    // The quadtree over everything's bounds, its leaves about 1 m across (depth up to 7).
    Eigen::AlignedBox3d all(Eigen::Vector3d::Zero());
    for (const ObjectGeometry& g : geometry.objects)
      if (!g.bbox_world.isEmpty()) all.extend(g.bbox_world);
    const Eigen::Vector3d c = all.center(), e = all.sizes().cwiseMax(1.0);
    const int depth = std::clamp(static_cast<int>(std::ceil(std::log2(std::max(e.x(), e.y())))), 1, 7);
    dVector3 centre = {c.x(), c.y(), c.z(), 0}, extents = {e.x(), e.y(), e.z(), 0};
    w.scenery = dQuadTreeSpaceCreate(nullptr, centre, extents, depth);
  }
  w.contact_group = dJointGroupCreate(0);
  const size_t n = wc.objects.size();
  w.geoms.resize(n);
  w.bodies.assign(n, nullptr);
  w.X_body_object.assign(n, Eigen::Isometry3d::Identity());
  w.masses.assign(n, 0);
  w.still_for.assign(n, 0);
  w.recent.assign(n, {});
  w.touching.assign(n, {});
  w.device_force.assign(n, Eigen::Vector3d::Zero());
  w.device_pushing.assign(n, -1);
  // Containers (rooms: `container: true` types) are spaces, not solids: they are not collision
  // geometry. The floor is the plane at the bottom of the lowest of them (or z = 0).
  const std::vector<char> container = containers(wc);
  w.zone.assign(n, 0);
  for (size_t i = 0; i < n; ++i) w.zone[i] = wc.types[wc.objects[i].type].zone;
  const double floor = sscs::floor_z(wc, geometry);
  w.floor = floor;
  dGeomID plane = dCreatePlane(w.scenery, 0, 0, 1, floor);
  w.tag(plane, -1, -1);
  // Rooms above the lowest stand on floors of their own: ground down to the plane beside a pit,
  // a slab under a mezzanine (floor_blocks).
  for (const FloorBlock& block : floor_blocks(wc, geometry)) {
    dGeomID g = dCreateBox(w.scenery, block.size.x(), block.size.y(), block.size.z());
    Impl::place(g, block.X_world_centre);
    w.tag(g, -1, -1);
  }
  for (size_t i = 0; i < n; ++i) {
    if (container[i]) continue;
    const ObjectGeometry& g = geometry.objects[i];
    for (const Shape& s : g.shapes) {
      dGeomID geom = w.make_geom(s);
      w.add_geom(geom);
      Impl::place(geom, g.X_world_object * s.X_object_shape);
      w.tag(geom, static_cast<int>(i), s.part);
      w.geoms[i].push_back(geom);
    }
  }
}

PhysicsWorld::~PhysicsWorld() {
  if (impl_->broken) return;  // left as it is: destroying a space ODE failed inside (locked) fails again
  Impl& w = *impl_;
  dJointGroupDestroy(w.contact_group);
  dSpaceDestroy(w.space);  // destroys its geoms
  dSpaceDestroy(w.scenery);
  for (dTriMeshDataID m : w.meshes) dGeomTriMeshDataDestroy(m);
  dWorldDestroy(w.world);
}

void PhysicsWorld::make_dynamic(int o) {
  Impl& w = *impl_;
  if (w.bodies[o] || w.geoms[o].empty()) return;
  const ObjectGeometry& g = w.geometry.objects[o];
  double m = object_mass(w.wc, w.geometry, o);
  // Inertia: the single primitive's own, or a box of the object's bounds; the body sits at the
  // centre of mass (ODE's convention), the object's frame at an offset from it.
  dMass mass;
  dMassSetZero(&mass);
  Eigen::Vector3d centre = g.bbox_world.center();
  if (g.shapes.size() == 1 && g.shapes[0].kind != Shape::Kind::Mesh) {
    const Shape& s = g.shapes[0];
    switch (s.kind) {
      case Shape::Kind::Box: dMassSetBoxTotal(&mass, m, s.box_size.x(), s.box_size.y(), s.box_size.z()); break;
      case Shape::Kind::Cylinder: dMassSetCylinderTotal(&mass, m, 3, s.radius, s.length); break;
      default: dMassSetSphereTotal(&mass, m, s.radius); break;
    }
    dMatrix3 R;
    to_ode(s.X_object_shape.linear(), R);
    dMassRotate(&mass, R);
    centre = g.X_world_object * s.X_object_shape.translation();
  }
  Eigen::Matrix3d I;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) I(r, c) = mass.I[r * 4 + c];
  // A primitive too small for its mass (a 1 mm sphere of 20 kg) is simulated as the box around it
  // at least 1 mm a side, as an object of meshes is; the plan refused masses beyond the range.
  if (g.shapes.size() != 1 || g.shapes[0].kind == Shape::Kind::Mesh || !unphysical_inertia(m, I).empty()) {
    Eigen::Vector3d size = g.bbox_world.sizes().cwiseMax(1e-3);
    dMassSetBoxTotal(&mass, m, size.x(), size.y(), size.z());
    centre = g.bbox_world.center();
  }
  // The current pose: where the object is now (static so far: its geometry's pose).
  Eigen::Isometry3d X_world_object = g.X_world_object;
  Eigen::Isometry3d X_world_body = X_world_object;
  X_world_body.translation() = centre;
  dBodyID body = dBodyCreate(w.world);
  dBodySetPosition(body, centre.x(), centre.y(), centre.z());
  dMatrix3 R;
  to_ode(X_world_body.linear(), R);
  dBodySetRotation(body, R);
  dBodySetMass(body, &mass);
  for (size_t k = 0; k < w.geoms[o].size(); ++k) {
    dGeomID geom = w.geoms[o][k];
    const dReal* p = dGeomGetPosition(geom);
    dMatrix3 Rg;
    std::copy(dGeomGetRotation(geom), dGeomGetRotation(geom) + 12, Rg);
    Eigen::Vector3d pos(p[0], p[1], p[2]);
    dGeomSetBody(geom, body);
    dSpaceRemove(w.scenery, geom);
    dSpaceAdd(w.space, geom);
    dGeomSetOffsetWorldPosition(geom, pos.x(), pos.y(), pos.z());
    dGeomSetOffsetWorldRotation(geom, Rg);
  }
  w.bodies[o] = body;
  w.masses[o] = m;
  w.X_body_object[o] = X_world_body.inverse() * X_world_object;
}

void PhysicsWorld::add_device(int o, const Eigen::VectorXd& q) {
  Impl& w = *impl_;
  const ObjectGeometry& g = w.geometry.objects[o];
  if (!g.device || w.devices.count(o)) return;
  const Device& d = *g.device;
  for (dGeomID geom : w.geoms[o]) dGeomDestroy(geom);
  w.geoms[o].clear();
  DeviceBodies& db = w.devices[o];
  db.kinematic = d.kinematic || w.options.fast;
  db.bodies.assign(d.parts.size(), nullptr);
  db.X_body_part.assign(d.parts.size(), Eigen::Isometry3d::Identity());
  std::vector<Eigen::Isometry3d> X = d.part_poses(q);
  for (auto& x : X) x = g.X_world_object * x;
  // The root, and parts fixed to it through fixed joints only (a URDF's `world` link holding
  // base_link), stand where the device stands: scenery, with no body to sag or touch the floor.
  const std::vector<char> moved = d.moved_parts();
  for (size_t p = 0; p < d.parts.size(); ++p) {
    const Part& part = d.parts[p];
    dBodyID body = nullptr;
    if (moved[p]) {
      // Mass: the part's, else 1 kg; inertia: the part's (URDF) when physical (the import warned of
      // one that is not), else the box of its shapes' bounds.
      double m = simulable_mass(part.mass) ? part.mass : 1.0;  // the import warned of one beyond the range
      dMass mass;
      Eigen::Vector3d com = Eigen::Vector3d::Zero();
      if (part.inertia && part.com && unphysical_inertia(m, *part.inertia).empty()) {
        com = *part.com;
        const Eigen::Matrix3d& I = *part.inertia;
        dMassSetParameters(&mass, m, 0, 0, 0, I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2));
      } else {
        Eigen::AlignedBox3d box;
        for (const Shape& s : part.shapes) box.extend(shape_bounds(s, s.X_object_shape));
        Eigen::Vector3d size = box.isEmpty() ? Eigen::Vector3d::Constant(0.1) : Eigen::Vector3d(box.sizes().cwiseMax(0.01));
        if (!box.isEmpty()) com = box.center();
        dMassSetBoxTotal(&mass, m, size.x(), size.y(), size.z());
      }
      body = dBodyCreate(w.world);
      Eigen::Isometry3d X_body = X[p] * Eigen::Translation3d(com);
      dBodySetPosition(body, X_body.translation().x(), X_body.translation().y(), X_body.translation().z());
      dMatrix3 R;
      to_ode(X_body.linear(), R);
      dBodySetRotation(body, R);
      dBodySetMass(body, &mass);
      dBodySetAutoDisableFlag(body, 0);  // driven parts never sleep
      if (db.kinematic) dBodySetKinematic(body);
      db.X_body_part[p] = Eigen::Isometry3d(Eigen::Translation3d(-com));
    }
    db.bodies[p] = body;
    for (const Shape& s : part.shapes) {
      dGeomID geom = w.make_geom(s);
      if (body) dGeomSetBody(geom, body);
      w.add_geom(geom);
      Impl::place(geom, X[p] * s.X_object_shape);
      w.tag(geom, o, static_cast<int>(p));
      w.geoms[o].push_back(geom);
    }
  }
  db.joints.resize(d.dof());
  db.commanded = q;
  if (!db.kinematic) w.join_parts(o, db, q);
}

void PhysicsWorld::drive(int o, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  Impl& w = *impl_;
  auto it = w.devices.find(o);
  if (it == w.devices.end()) return;
  DeviceBodies& db = it->second;
  const ObjectGeometry& g = w.geometry.objects[o];
  const Device& d = *g.device;
  if (db.kinematic) {
    // Placed on the plan, with the velocities that take them there (for contacts with them).
    std::vector<Eigen::Isometry3d> X = d.part_poses(q);
    db.target.resize(d.parts.size());
    for (size_t p = 0; p < d.parts.size(); ++p) {
      dBodyID b = db.bodies[p];
      if (!b) continue;
      db.target[p] = compose(compose(g.X_world_object, X[p]), db.X_body_part[p].inverse());
      Impl::aim(b, db.target[p], w.options.timestep);
    }
    db.commanded = q;
    // Fast mode: what the tool holds goes with it, rigidly.
    if (auto grip = w.grips.find(o); grip != w.grips.end() && !grip->second.joint && db.bodies[d.tool_part]) {
      grip->second.target = db.target[d.tool_part] * grip->second.X_tool_load;
      Impl::aim(w.bodies[grip->second.object], grip->second.target, w.options.timestep);
    }
    return;
  }
  // Motors: the planned velocity plus a proportional correction of the error against where the
  // plan is now (q less this step's motion). The correction once aimed at q, the plan a step
  // ahead, which made every motor run 20/s x dt faster than planned: a tool led its plan by
  // 3 cm at a 20 ms timestep (1.5 mm at the default 1 ms), a false `tracking_error`.
  constexpr double kGain = 20;  // 1/s
  const double dt = w.options.timestep;
  Eigen::VectorXd now = joints(o);
  for (int k = 0; k < d.dof(); ++k) {
    const auto& rec = db.joints[k];
    if (!rec.joint) continue;
    double v = qd[k] + kGain * (q[k] - qd[k] * dt - now[k]);
    if (rec.type == JointType::Revolute) dJointSetHingeParam(rec.joint, dParamVel, v);
    else dJointSetSliderParam(rec.joint, dParamVel, v);
  }
}

Eigen::VectorXd PhysicsWorld::joints(int o) const {
  const Impl& w = *impl_;
  const Device& d = *w.geometry.objects[o].device;
  auto it = w.devices.find(o);
  if (it == w.devices.end())
    return d.joint_values(&w.wc.values[w.wc.objects[o].first_slot + kFirstAttributeSlot]);
  const DeviceBodies& db = it->second;
  Eigen::VectorXd q(d.dof());
  if (db.kinematic) return db.commanded;  // kinematic parts follow the plan exactly
  for (int k = 0; k < d.dof(); ++k) {
    const auto& rec = db.joints[k];
    if (!rec.joint) continue;
    q[k] = rec.q_attach + rec.unwrapped;
  }
  return q;
}

Eigen::Isometry3d PhysicsWorld::part_pose(int o, int p) const {
  const Impl& w = *impl_;
  const ObjectGeometry& g = w.geometry.objects[o];
  auto it = w.devices.find(o);
  if (it == w.devices.end() || !it->second.bodies[p]) return compose(g.X_world_object, g.X_object_part[p]);
  dBodyID b = it->second.bodies[p];
  return compose(from_ode(dBodyGetPosition(b), dBodyGetRotation(b)), it->second.X_body_part[p]);
}

void PhysicsWorld::grasp(int device, int o) {
  Impl& w = *impl_;
  auto it = w.devices.find(device);
  if (it == w.devices.end() || w.grips.count(device)) return;
  make_dynamic(o);
  if (!w.bodies[o]) return;  // no solid (the plan refuses containers): nothing to hold
  const Device& d = *w.geometry.objects[device].device;
  Impl::Grip grip;
  grip.object = o;
  grip.tool_parts = d.tool_parts();
  dBodyID tool = it->second.bodies[d.tool_part];
  if (w.options.fast && tool && it->second.kinematic) {
    // Fast mode: the load moves rigidly with the tool, a kinematic body placed with it.
    grip.X_tool_load = from_ode(dBodyGetPosition(tool), dBodyGetRotation(tool)).inverse() *
                       from_ode(dBodyGetPosition(w.bodies[o]), dBodyGetRotation(w.bodies[o]));
    grip.target = from_ode(dBodyGetPosition(w.bodies[o]), dBodyGetRotation(w.bodies[o]));
    dBodySetKinematic(w.bodies[o]);
  } else {
    grip.joint = dJointCreateFixed(w.world, nullptr);
    dJointAttach(grip.joint, w.bodies[o], tool);  // a null tool body (a fixed tool) holds it to the world
    dJointSetFixed(grip.joint);
  }
  dBodyEnable(w.bodies[o]);
  w.grips[device] = std::move(grip);
}

void PhysicsWorld::release(int device) {
  Impl& w = *impl_;
  auto it = w.grips.find(device);
  if (it == w.grips.end()) return;
  if (it->second.joint) dJointDestroy(it->second.joint);
  else dBodySetDynamic(w.bodies[it->second.object]);  // fast mode: free again, moving as the tool did
  dBodyEnable(w.bodies[it->second.object]);
  w.still_for[it->second.object] = 0;  // held still is no rest: it is judged from its release
  w.recent[it->second.object].samples.clear();
  w.grips.erase(it);
}

void PhysicsWorld::ride(int rider, int support) {
  Impl& w = *impl_;
  if (!w.options.weld_riders || rider == support || !w.bodies[rider] || support < 0 || !w.bodies[support]) return;
  stop_riding(rider);
  w.rides[rider].support = support;
}

void PhysicsWorld::stop_riding(int rider) {
  Impl& w = *impl_;
  auto it = w.rides.find(rider);
  if (it == w.rides.end()) return;
  w.unweld(it->second, rider);
  w.rides.erase(it);
}

bool PhysicsWorld::welded(int rider) const {
  auto it = impl_->rides.find(rider);
  return it != impl_->rides.end() && it->second.weld;
}

int PhysicsWorld::held(int device) const {
  auto it = impl_->grips.find(device);
  return it == impl_->grips.end() ? -1 : it->second.object;
}

bool PhysicsWorld::dynamic(int o) const { return impl_->bodies[o] != nullptr; }

void PhysicsWorld::set_present(int o, bool present) {
  for (dGeomID geom : impl_->geoms[o]) {
    if (present) dGeomEnable(geom);
    else dGeomDisable(geom);
  }
}

bool PhysicsWorld::at_rest(int o) const {
  const Impl& w = *impl_;
  return w.bodies[o] && (!dBodyIsEnabled(w.bodies[o]) || w.still_for[o] >= kRestTime - 1e-9);
}

void PhysicsWorld::step() {
  Impl& w = *impl_;
  w.contacts.clear();
  w.contact_index.clear();
  g_messages = &w.messages;
  g_message_time = w.time;
  for (auto& [rider, r] : w.rides) r.points.clear(), r.normals.clear();
  try {
    Impl::collide(&w);
    w.wake_unsupported();
    if (!w.options.fast || w.dynamics_needed()) {
      dWorldStep(w.world, w.options.timestep);
      w.sum_device_forces();
      w.update_rides();
      ++w.dynamics_steps;
    } else {  // nothing moves or is pushed: no device exerts a force (a stale push read as propping)
      w.feedback.clear();
      w.feedback_of.clear();
      if (w.pushed_last_step) {
        std::fill(w.device_force.begin(), w.device_force.end(), Eigen::Vector3d::Zero());
        std::fill(w.device_pushing.begin(), w.device_pushing.end(), -1);
        w.pushed_last_step = false;
      }
    }
    if (w.options.fast) w.place_kinematic();
  } catch (const PhysicsFailure&) {
    w.broken = true;
    g_messages = nullptr;
    throw;
  }
  g_messages = nullptr;
  dJointGroupEmpty(w.contact_group);
  for (auto& [o, db] : w.devices)
    for (auto& rec : db.joints) {
      if (!rec.joint) continue;
      double now = rec.type == JointType::Revolute ? dJointGetHingeAngle(rec.joint) : dJointGetSliderPosition(rec.joint);
      double d = now - rec.raw;
      if (rec.type == JointType::Revolute) d = std::remainder(d, 2 * std::numbers::pi);
      rec.unwrapped += d;
      rec.raw = now;
    }
  // Rest as ODE's auto-disable judges it, measured here too: a body touching a driven part
  // (a pallet set down on the forks still in its pockets) is never disabled, being in one
  // island with parts that never sleep, though it lies still.
  for (size_t o = 0; o < w.bodies.size(); ++o) {
    if (!w.bodies[o]) continue;
    const dReal* v = dBodyGetLinearVel(w.bodies[o]);
    const dReal* a = dBodyGetAngularVel(w.bodies[o]);
    Impl::Velocities& r = w.recent[o];
    const Eigen::Matrix<double, 6, 1> now = (Eigen::Matrix<double, 6, 1>() << v[0], v[1], v[2], a[0], a[1], a[2]).finished();
    if (r.samples.size() < w.rest_samples) r.samples.push_back(now);
    else r.samples[r.next] = now;
    r.next = (r.next + 1) % w.rest_samples;
    // As ODE judges it: only a full window of samples is averaged.
    Eigen::Matrix<double, 6, 1> mean = Eigen::Matrix<double, 6, 1>::Zero();
    for (const auto& x : r.samples) mean += x;
    mean /= static_cast<double>(r.samples.size());
    const bool still = r.samples.size() == w.rest_samples && mean.head<3>().norm() < kRestSpeed && mean.tail<3>().norm() < kRestTurn;
    w.still_for[o] = still ? w.still_for[o] + w.options.timestep : 0;
    // Fast mode: at rest, it sleeps (ODE's auto-disable judges only the steps it takes), unless
    // it touches a device or what one holds: leaning on a tool, the tool's push decides whether
    // it is propped, and ODE never puts such a body to sleep either (one island with parts that
    // never sleep).
    if (w.options.fast && w.still_for[o] >= kRestTime - 1e-9 && dBodyIsEnabled(w.bodies[o]) && !dBodyIsKinematic(w.bodies[o]) &&
        !w.rides.count(static_cast<int>(o)) && !w.touches_device(o))
      dBodyDisable(w.bodies[o]);
  }
  w.time += w.options.timestep;
}

const SolverMessages& PhysicsWorld::solver_messages() const { return impl_->messages; }
long PhysicsWorld::dynamics_steps() const { return impl_->dynamics_steps; }

bool PhysicsWorld::on_plan(int o) const {
  const Impl& w = *impl_;
  auto it = w.devices.find(o);
  return w.options.fast && it != w.devices.end() && it->second.kinematic && !w.handed.count(o);
}

int PhysicsWorld::rigid_load(int o, Eigen::Isometry3d* X_tool_load) const {
  const Impl& w = *impl_;
  auto grip = w.grips.find(o);
  if (!on_plan(o) || grip == w.grips.end() || grip->second.joint) return -1;
  if (X_tool_load) {  // the grip keeps the load's body in the tool's body; here its object in the tool part
    const Device& d = *w.geometry.objects[o].device;
    *X_tool_load = w.devices.at(o).X_body_part[d.tool_part].inverse() * grip->second.X_tool_load * w.X_body_object[grip->second.object];
  }
  return grip->second.object;
}

bool PhysicsWorld::quiet() const {
  const Impl& w = *impl_;
  if (!w.options.fast || !w.handed.empty() || !w.rides.empty()) return false;
  for (size_t o = 0; o < w.bodies.size(); ++o)
    if (w.bodies[o] && !dBodyIsKinematic(w.bodies[o]) && dBodyIsEnabled(w.bodies[o]) && w.still_for[o] < kRestTime - 1e-9) return false;
  return true;
}

void PhysicsWorld::place(int o, const Eigen::VectorXd& q) {
  Impl& w = *impl_;
  auto it = w.devices.find(o);
  if (it == w.devices.end() || !it->second.kinematic) return;
  drive(o, q, Eigen::VectorXd::Zero(q.size()));  // its targets (and its load's)
  DeviceBodies& db = it->second;
  for (size_t p = 0; p < db.bodies.size() && p < db.target.size(); ++p)
    if (db.bodies[p]) {
      Impl::place_body(db.bodies[p], db.target[p]);
      dBodySetLinearVel(db.bodies[p], 0, 0, 0);
      dBodySetAngularVel(db.bodies[p], 0, 0, 0);
    }
  if (auto grip = w.grips.find(o); grip != w.grips.end() && !grip->second.joint && w.bodies[grip->second.object]) {
    Impl::place_body(w.bodies[grip->second.object], grip->second.target);
    dBodySetLinearVel(w.bodies[grip->second.object], 0, 0, 0);
    dBodySetAngularVel(w.bodies[grip->second.object], 0, 0, 0);
  }
}

void PhysicsWorld::advance(double seconds) {
  Impl& w = *impl_;
  w.contacts.clear();
  w.contact_index.clear();
  for (size_t o = 0; o < w.bodies.size(); ++o)
    if (w.bodies[o] && !dBodyIsKinematic(w.bodies[o])) w.still_for[o] += seconds;
  w.time += seconds;
}

bool PhysicsWorld::hand_over(int o, const Eigen::VectorXd* q_from) {
  Impl& w = *impl_;
  auto it = w.devices.find(o);
  if (!w.options.fast || it == w.devices.end() || !it->second.kinematic || w.geometry.objects[o].device->kinematic) return false;
  DeviceBodies& db = it->second;
  if (q_from) {  // back to where it was before the step, its velocities kept (the plan's)
    const ObjectGeometry& g = w.geometry.objects[o];
    const std::vector<Eigen::Isometry3d> X = g.device->part_poses(*q_from);
    auto grip = w.grips.find(o);
    const bool rigid = grip != w.grips.end() && !grip->second.joint;
    for (size_t p = 0; p < db.bodies.size(); ++p)
      if (db.bodies[p]) Impl::place_body(db.bodies[p], compose(compose(g.X_world_object, X[p]), db.X_body_part[p].inverse()));
    if (rigid && db.bodies[g.device->tool_part]) {
      const dBodyID tool = db.bodies[g.device->tool_part];
      Impl::place_body(w.bodies[grip->second.object], from_ode(dBodyGetPosition(tool), dBodyGetRotation(tool)) * grip->second.X_tool_load);
    }
    db.commanded = *q_from;
  }
  for (dBodyID b : db.bodies)
    if (b) dBodySetDynamic(b);
  db.kinematic = false;
  db.target.clear();
  w.join_parts(o, db, db.commanded);
  if (auto grip = w.grips.find(o); grip != w.grips.end() && !grip->second.joint) {
    const dBodyID load = w.bodies[grip->second.object];
    dBodySetDynamic(load);
    grip->second.joint = dJointCreateFixed(w.world, nullptr);
    dJointAttach(grip->second.joint, load, db.bodies[w.geometry.objects[o].device->tool_part]);
    dJointSetFixed(grip->second.joint);
  }
  w.handed.insert(o);
  return true;
}

double PhysicsWorld::time() const { return impl_->time; }
double PhysicsWorld::floor_z() const { return impl_->floor; }
double PhysicsWorld::mass(int o) const { return impl_->masses[o]; }
const std::vector<PhysicsContact>& PhysicsWorld::contacts() const { return impl_->contacts; }
Eigen::Vector3d PhysicsWorld::device_force(int o) const { return impl_->device_force[o]; }
int PhysicsWorld::device_pushing(int o) const { return impl_->device_pushing[o]; }

OdeHandles PhysicsWorld::ode_handles(int object) const {
  const Impl& w = *impl_;
  OdeHandles h{w.world, w.contact_group, &Impl::collide, const_cast<Impl*>(&w), {}};
  auto it = w.devices.find(object);
  if (it != w.devices.end() && !it->second.kinematic)
    for (const auto& rec : it->second.joints) h.motors.push_back({rec.joint, rec.type == JointType::Revolute, rec.q_attach});
  return h;
}

Eigen::Isometry3d PhysicsWorld::pose(int o) const {
  const Impl& w = *impl_;
  if (!w.bodies[o]) return w.geometry.objects[o].X_world_object;
  return from_ode(dBodyGetPosition(w.bodies[o]), dBodyGetRotation(w.bodies[o])) * w.X_body_object[o];
}

Eigen::Vector3d PhysicsWorld::velocity(int o) const {
  const Impl& w = *impl_;
  if (!w.bodies[o]) return Eigen::Vector3d::Zero();
  const dReal* v = dBodyGetLinearVel(w.bodies[o]);
  return {v[0], v[1], v[2]};
}

}  // namespace sscs
