#include "simulate/world.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>

#include <ode/ode.h>

#include "kinematics/device.h"

namespace sscs {

namespace {

constexpr double kGravity = 9.80665;
constexpr int kMaxContacts = 8;      // per geom pair and step
constexpr double kDefaultDensity = 500;  // kg/m^3, for objects that state no mass

void init_ode() {
  static std::once_flag once;
  std::call_once(once, [] { dInitODE2(0); });
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

/// An object's mass: its `mass` attribute, else the sum of `tare_mass`, `fill_mass` and
/// `payload_mass` (a drum, a container), else its bounds' volume at 500 kg/m^3.
double object_mass(const Workcell& wc, const GeometryModel& geometry, int o) {
  const Object& obj = wc.objects[o];
  const ObjectType& t = wc.types[obj.type];
  auto attr = [&](const char* name) -> std::optional<double> {
    int a = t.find_attribute(name);
    if (a < 0) return std::nullopt;
    return wc.values[obj.first_slot + kFirstAttributeSlot + a];
  };
  if (auto m = attr("mass"); m && *m > 0) return *m;
  double sum = 0;
  for (const char* n : {"tare_mass", "fill_mass", "payload_mass"})
    if (auto m = attr(n)) sum += *m;
  if (sum > 0) return sum;
  Eigen::Vector3d size = geometry.objects[o].bbox_world.sizes();
  return std::max(kDefaultDensity * size.prod(), 0.1);
}

}  // namespace

struct PhysicsWorld::Impl {
  const Workcell& wc;
  const GeometryModel& geometry;
  PhysicsOptions options;
  dWorldID world = nullptr;
  dSpaceID space = nullptr;
  dJointGroupID contact_group = nullptr;
  double floor = 0;
  double time = 0;
  std::vector<std::vector<dGeomID>> geoms;  // per object
  std::vector<dBodyID> bodies;              // per object; null when static
  std::vector<Eigen::Isometry3d> X_body_object;
  std::vector<double> masses;
  std::vector<dTriMeshDataID> meshes;
  std::vector<std::vector<double>> mesh_vertices;
  std::vector<std::vector<int>> mesh_indices;
  std::vector<PhysicsContact> contacts;
  std::map<std::pair<int, int>, size_t> contact_index;

  Impl(const Workcell& w, const GeometryModel& g, const PhysicsOptions& o) : wc(w), geometry(g), options(o) {}

  dGeomID make_geom(const Shape& s) {
    switch (s.kind) {
      case Shape::Kind::Box: return dCreateBox(space, s.box_size.x(), s.box_size.y(), s.box_size.z());
      case Shape::Kind::Cylinder: return dCreateCylinder(space, s.radius, s.length);
      case Shape::Kind::Sphere: return dCreateSphere(space, s.radius);
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
        return dCreateTriMesh(space, data, nullptr, nullptr, nullptr);
      }
    }
    return nullptr;
  }

  static void near_callback(void* data, dGeomID g1, dGeomID g2) { static_cast<Impl*>(data)->near(g1, g2); }

  void near(dGeomID g1, dGeomID g2) {
    dBodyID b1 = dGeomGetBody(g1), b2 = dGeomGetBody(g2);
    if (!b1 && !b2) return;  // scenery does not collide with scenery
    if (b1 == b2) return;
    int o1 = static_cast<int>(reinterpret_cast<intptr_t>(dGeomGetData(g1)));
    int o2 = static_cast<int>(reinterpret_cast<intptr_t>(dGeomGetData(g2)));
    if (o1 == o2) return;
    dContact contact[kMaxContacts];
    int n = dCollide(g1, g2, kMaxContacts, &contact[0].geom, sizeof(dContact));
    for (int i = 0; i < n; ++i) {
      dContact& c = contact[i];
      c.surface.mode = dContactBounce | dContactSoftCFM | dContactApprox1;
      c.surface.mu = options.friction;
      c.surface.bounce = options.restitution;
      c.surface.bounce_vel = 0.1;
      c.surface.soft_cfm = 1e-6;
      dJointID j = dJointCreateContact(world, contact_group, &c);
      dJointAttach(j, b1, b2);
      auto key = std::minmax(o1, o2);
      auto [it, fresh] = contact_index.try_emplace({key.first, key.second}, contacts.size());
      if (fresh) contacts.push_back({key.first, key.second, Eigen::Vector3d::Zero(), -1});
      PhysicsContact& pc = contacts[it->second];
      if (c.geom.depth > pc.depth) {
        pc.depth = c.geom.depth;
        pc.point = Eigen::Vector3d(c.geom.pos[0], c.geom.pos[1], c.geom.pos[2]);
      }
    }
  }
};

PhysicsWorld::PhysicsWorld(const Workcell& wc, const GeometryModel& geometry, const PhysicsOptions& options)
    : impl_(std::make_unique<Impl>(wc, geometry, options)) {
  init_ode();
  Impl& w = *impl_;
  w.world = dWorldCreate();
  dWorldSetGravity(w.world, 0, 0, options.gravity ? -kGravity : 0);
  dWorldSetERP(w.world, 0.2);
  dWorldSetCFM(w.world, 1e-9);
  // A body slower than 5 mm/s and 0.01 rad/s for 0.2 s is at rest: ODE stops integrating it
  // (which also ends the contact jitter of meshes) until something touches or moves it.
  dWorldSetAutoDisableFlag(w.world, 1);
  dWorldSetAutoDisableLinearThreshold(w.world, 0.005);
  dWorldSetAutoDisableAngularThreshold(w.world, 0.01);
  dWorldSetAutoDisableTime(w.world, 0.2);
  dWorldSetAutoDisableSteps(w.world, 0);
  w.space = dHashSpaceCreate(nullptr);
  dHashSpaceSetLevels(w.space, -4, 6);  // cells from 6 cm to 64 m
  w.contact_group = dJointGroupCreate(0);
  const size_t n = wc.objects.size();
  w.geoms.resize(n);
  w.bodies.assign(n, nullptr);
  w.X_body_object.assign(n, Eigen::Isometry3d::Identity());
  w.masses.assign(n, 0);
  // Objects that hold others (rooms, containers) are spaces, not solids: they are not
  // collision geometry. The floor is the plane at the bottom of the lowest of them (or z = 0).
  std::vector<char> container(n, 0);
  for (const Object& o : wc.objects)
    if (o.parent >= 0) container[o.parent] = 1;
  bool any_container = false;
  double floor = 0;
  for (size_t i = 0; i < n; ++i)
    if (container[i] && !geometry.objects[i].bbox_world.isEmpty()) {
      floor = any_container ? std::min(floor, geometry.objects[i].bbox_world.min().z()) : geometry.objects[i].bbox_world.min().z();
      any_container = true;
    }
  w.floor = floor;
  dGeomID plane = dCreatePlane(w.space, 0, 0, 1, floor);
  dGeomSetData(plane, reinterpret_cast<void*>(static_cast<intptr_t>(-1)));
  for (size_t i = 0; i < n; ++i) {
    if (container[i]) continue;
    const ObjectGeometry& g = geometry.objects[i];
    for (const Shape& s : g.shapes) {
      dGeomID geom = w.make_geom(s);
      Eigen::Isometry3d X = g.X_world_object * s.X_object_shape;
      dGeomSetPosition(geom, X.translation().x(), X.translation().y(), X.translation().z());
      dMatrix3 R;
      to_ode(X.linear(), R);
      dGeomSetRotation(geom, R);
      dGeomSetData(geom, reinterpret_cast<void*>(static_cast<intptr_t>(i)));
      w.geoms[i].push_back(geom);
    }
  }
}

PhysicsWorld::~PhysicsWorld() {
  Impl& w = *impl_;
  dJointGroupDestroy(w.contact_group);
  dSpaceDestroy(w.space);  // destroys its geoms
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
  Eigen::Vector3d centre;
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
  } else {
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
    dGeomSetOffsetWorldPosition(geom, pos.x(), pos.y(), pos.z());
    dGeomSetOffsetWorldRotation(geom, Rg);
  }
  w.bodies[o] = body;
  w.masses[o] = m;
  w.X_body_object[o] = X_world_body.inverse() * X_world_object;
}

bool PhysicsWorld::dynamic(int o) const { return impl_->bodies[o] != nullptr; }

bool PhysicsWorld::at_rest(int o) const { return impl_->bodies[o] && !dBodyIsEnabled(impl_->bodies[o]); }

void PhysicsWorld::step() {
  Impl& w = *impl_;
  w.contacts.clear();
  w.contact_index.clear();
  dSpaceCollide(w.space, &w, &Impl::near_callback);
  dWorldStep(w.world, w.options.timestep);
  dJointGroupEmpty(w.contact_group);
  w.time += w.options.timestep;
}

double PhysicsWorld::time() const { return impl_->time; }
double PhysicsWorld::floor_z() const { return impl_->floor; }
double PhysicsWorld::mass(int o) const { return impl_->masses[o]; }
const std::vector<PhysicsContact>& PhysicsWorld::contacts() const { return impl_->contacts; }

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
