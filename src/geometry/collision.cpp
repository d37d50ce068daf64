#include "geometry/collision.h"

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace sscs {

namespace {

std::shared_ptr<fcl::CollisionGeometryd> make_geometry(const Shape& s) {
  switch (s.kind) {
    case Shape::Kind::Box: return std::make_shared<fcl::Boxd>(s.box_size.x(), s.box_size.y(), s.box_size.z());
    case Shape::Kind::Cylinder: return std::make_shared<fcl::Cylinderd>(s.radius, s.length);
    case Shape::Kind::Sphere: return std::make_shared<fcl::Sphered>(s.radius);
    case Shape::Kind::Mesh: {
      auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
      std::vector<fcl::Vector3d> vertices;
      vertices.reserve(s.mesh->vertices.size());
      for (const Eigen::Vector3d& v : s.mesh->vertices) vertices.push_back(v.cwiseProduct(s.scale));
      std::vector<fcl::Triangle> triangles;
      triangles.reserve(s.mesh->triangles.size());
      for (const Eigen::Vector3i& t : s.mesh->triangles) triangles.emplace_back(t.x(), t.y(), t.z());
      model->beginModel();
      model->addSubModel(vertices, triangles);
      model->endModel();
      return model;
    }
  }
  return nullptr;
}

}  // namespace

struct CollisionWorld::Impl {
  const GeometryModel& geometry;
  // Per object, its shapes as FCL objects in world placement. Built on first use.
  std::map<int, std::vector<std::unique_ptr<fcl::CollisionObjectd>>> parts;

  const std::vector<std::unique_ptr<fcl::CollisionObjectd>>& of(int object) {
    auto it = parts.find(object);
    if (it != parts.end()) return it->second;
    auto& list = parts[object];
    const ObjectGeometry& g = geometry.objects[object];
    for (const Shape& s : g.shapes) {
      Eigen::Isometry3d X = g.X_world_object * s.X_object_shape;
      auto obj = std::make_unique<fcl::CollisionObjectd>(make_geometry(s), fcl::Transform3d(X.matrix()));
      obj->computeAABB();
      list.push_back(std::move(obj));
    }
    return list;
  }
};

CollisionWorld::CollisionWorld(const GeometryModel& geometry) : impl_(std::make_unique<Impl>(Impl{geometry, {}})) {}
CollisionWorld::~CollisionWorld() = default;

std::optional<double> CollisionWorld::distance(int a, int b) {
  const auto& pa = impl_->of(a);
  const auto& pb = impl_->of(b);
  if (pa.empty() || pb.empty()) return std::nullopt;
  double best = INFINITY;
  double deepest = 0;
  for (const auto& x : pa)
    for (const auto& y : pb) {
      fcl::CollisionRequestd creq(1, /*enable_contact=*/true);
      fcl::CollisionResultd cres;
      if (fcl::collide(x.get(), y.get(), creq, cres) > 0) {
        double depth = 0;
        for (size_t k = 0; k < cres.numContacts(); ++k) depth = std::max(depth, cres.getContact(k).penetration_depth);
        deepest = std::max(deepest, std::max(depth, 0.0));
        best = std::min(best, 0.0);
        continue;
      }
      // The independent GJK with a tight tolerance: libccd's default is off by centimetres on rotated boxes.
      fcl::DistanceRequestd dreq(false, false, 1e-9, 1e-9, 1e-9, fcl::GST_INDEP);
      fcl::DistanceResultd dres;
      fcl::distance(x.get(), y.get(), dreq, dres);
      best = std::min(best, dres.min_distance);
    }
  return deepest > 0 ? -deepest : best;
}

std::vector<std::pair<int, int>> CollisionWorld::candidate_pairs(const std::vector<int>& objects, double margin) {
  // Grown world boxes in a dynamic AABB tree; its self-collision query yields the touching pairs.
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> boxes;
  std::vector<fcl::CollisionObjectd*> registered;
  for (int o : objects) {
    const Eigen::AlignedBox3d& b = impl_->geometry.objects[o].bbox_world;
    if (b.isEmpty()) continue;
    Eigen::Vector3d size = b.sizes() + Eigen::Vector3d::Constant(2 * margin);
    auto box = std::make_shared<fcl::Boxd>(std::max(size.x(), 1e-9), std::max(size.y(), 1e-9), std::max(size.z(), 1e-9));
    fcl::Transform3d X = fcl::Transform3d::Identity();
    X.translation() = b.center();
    auto obj = std::make_unique<fcl::CollisionObjectd>(box, X);
    obj->setUserData(reinterpret_cast<void*>(static_cast<intptr_t>(o)));
    obj->computeAABB();
    registered.push_back(obj.get());
    boxes.push_back(std::move(obj));
  }
  fcl::DynamicAABBTreeCollisionManagerd manager;
  manager.registerObjects(registered);
  manager.setup();
  std::vector<std::pair<int, int>> pairs;
  auto callback = [](fcl::CollisionObjectd* a, fcl::CollisionObjectd* b, void* data) {
    auto* out = static_cast<std::vector<std::pair<int, int>>*>(data);
    int x = static_cast<int>(reinterpret_cast<intptr_t>(a->getUserData()));
    int y = static_cast<int>(reinterpret_cast<intptr_t>(b->getUserData()));
    // The manager calls back for pairs whose AABBs overlap; the grown boxes are axis-aligned,
    // so that is exactly "bounds within margin".
    out->emplace_back(std::min(x, y), std::max(x, y));
    return false;  // keep going
  };
  manager.collide(&pairs, callback);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

std::optional<double> inside_margin(const GeometryModel& geometry, int object, int container, std::string* why) {
  const ObjectGeometry& c = geometry.objects[container];
  if (c.shapes.size() != 1 || c.shapes[0].kind != Shape::Kind::Box) {
    *why = "the container must have exactly one box shape (its inside)";
    return std::nullopt;
  }
  const ObjectGeometry& g = geometry.objects[object];
  if (g.shapes.empty()) {
    *why = "the object has no geometry";
    return std::nullopt;
  }
  // Bounds of the object in the container box's own frame are exact for boxes, cylinders and
  // spheres (and vertex-exact for meshes); the box is axis-aligned there.
  Eigen::Isometry3d X_box_world = (c.X_world_object * c.shapes[0].X_object_shape).inverse();
  Eigen::Vector3d half = c.shapes[0].box_size / 2;
  Eigen::AlignedBox3d b;
  for (const Shape& s : g.shapes) b.extend(shape_bounds(s, X_box_world * g.X_world_object * s.X_object_shape));
  double margin = INFINITY;
  for (int k = 0; k < 3; ++k) margin = std::min({margin, b.min()[k] + half[k], half[k] - b.max()[k]});
  return margin;
}

}  // namespace sscs
