#include "geometry/collision.h"

#include "geometry/export.h"
#include "core/pose.h"

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <bit>
#include <filesystem>
#include <cmath>
#include <map>
#include <numbers>
#include <tuple>
#include <unordered_map>

#include "geometry/primitive_depth.h"
#include "model/device.h"

#include <fmt/format.h>

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

Eigen::Vector3d closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c);
bool inside_mesh(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& v, const std::vector<Eigen::Vector3i>& tris);
std::vector<Eigen::Vector3d> hull_points(const Shape& s, const Eigen::Isometry3d& X);

/// The shape a placed FCL object was made from (set as its user data).
const Shape& shape_of(const fcl::CollisionObjectd* o) { return *static_cast<const Shape*>(o->getUserData()); }

bool closed_mesh(const Shape& s) { return s.kind == Shape::Kind::Mesh && s.mesh && s.mesh->closed; }

/// The distance from p to a triangle mesh's surface (vertices and p in the mesh's frame).
double surface_distance(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& v, const std::vector<Eigen::Vector3i>& tris) {
  double d = INFINITY;
  for (const Eigen::Vector3i& t : tris) d = std::min(d, (p - closest_on_triangle(p, v[t.x()], v[t.y()], v[t.z()])).norm());
  return d;
}

/// A solid shape at a placement, for point queries: whether a point is inside, and how far it is
/// from the surface. Meshes must be closed.
struct Solid {
  const Shape& shape;
  Eigen::Isometry3d X_shape_world;
  std::vector<Eigen::Vector3d> vertices;  // meshes: scaled, in the shape's frame
  Eigen::AlignedBox3d bounds;              // meshes: of the vertices
  explicit Solid(const fcl::CollisionObjectd* o) : shape(shape_of(o)), X_shape_world(Eigen::Isometry3d(o->getTransform()).inverse()) {
    if (shape.kind == Shape::Kind::Mesh)
      for (const Eigen::Vector3d& v : shape.mesh->vertices) bounds.extend(vertices.emplace_back(v.cwiseProduct(shape.scale)));
  }
  bool contains(const Eigen::Vector3d& p_world) const {
    return shape.kind == Shape::Kind::Mesh ? inside_mesh(X_shape_world * p_world, vertices, shape.mesh->triangles)
                                           : depth_of(p_world) > 0;
  }
  /// A mesh's distance from p to its surface; -1 for primitives.
  double mesh_gap(const Eigen::Vector3d& p_world) const {
    return shape.kind == Shape::Kind::Mesh ? surface_distance(X_shape_world * p_world, vertices, shape.mesh->triangles) : -1;
  }
  /// Distance from the surface of a point inside (zero or negative when outside). A depth of at
  /// most `floor` may be answered as 0: for meshes the distance comes first and the inside test,
  /// the costlier, only when the point is deeper than that.
  double depth_of(const Eigen::Vector3d& p_world, double floor = 0) const {
    const Eigen::Vector3d p = X_shape_world * p_world;
    switch (shape.kind) {
      case Shape::Kind::Box: return ((shape.box_size / 2) - p.cwiseAbs()).minCoeff();
      case Shape::Kind::Cylinder: return std::min(shape.radius - p.head<2>().norm(), shape.length / 2 - std::abs(p.z()));
      case Shape::Kind::Sphere: return shape.radius - p.norm();
      case Shape::Kind::Mesh: {
        if (!bounds.contains(p)) return 0;
        double d = surface_distance(p, vertices, shape.mesh->triangles);
        return d > floor && inside_mesh(p, vertices, shape.mesh->triangles) ? d : 0;
      }
    }
    return 0;
  }
};

/// A placed shape's surface as world triangles: a mesh's own, a primitive's tessellation.
struct Surface {
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> t;
  explicit Surface(const fcl::CollisionObjectd* o) {
    const Shape& s = shape_of(o);
    const Eigen::Isometry3d X(o->getTransform());
    if (s.kind == Shape::Kind::Mesh) {
      for (const Eigen::Vector3d& p : s.mesh->vertices) v.push_back(X * p.cwiseProduct(s.scale));
      t = s.mesh->triangles;
    } else {
      Shape local = s;
      local.X_object_shape.setIdentity();
      TriangleMesh m = tessellate(local);
      for (const Eigen::Vector3d& p : m.vertices) v.push_back(X * p);
      t = std::move(m.triangles);
    }
  }
  Eigen::Vector3d corner(int tri, int k) const { return v[t[tri][k]]; }
  Eigen::Vector3d normal(int tri) const { return (corner(tri, 1) - corner(tri, 0)).cross(corner(tri, 2) - corner(tri, 0)); }
  Eigen::AlignedBox3d box(int tri) const {
    Eigen::AlignedBox3d b(corner(tri, 0));
    return b.extend(corner(tri, 1)).extend(corner(tri, 2));
  }
  /// Whether p (in the triangle's plane) lies in triangle `tri`, within `slack` of its edges.
  bool covers(int tri, const Eigen::Vector3d& p, double slack) const {
    const Eigen::Vector3d n = normal(tri).normalized();
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d a = corner(tri, k), b = corner(tri, (k + 1) % 3);
      if (n.cross(b - a).normalized().dot(p - a) < -slack) return false;
    }
    return true;
  }
};

/// Where segment pq crosses triangle abc, if it does (not when they are parallel).
std::optional<Eigen::Vector3d> segment_crossing(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                                                const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double dp = n.dot(p - a), dq = n.dot(q - a);
  if ((dp > 0 && dq > 0) || (dp < 0 && dq < 0) || dp == dq) return std::nullopt;
  const Eigen::Vector3d x = p + (q - p) * (dp / (dp - dq));
  // Inside abc: on the inner side of its three edges (up to rounding).
  const double slack = 1e-12 * n.norm();
  for (const auto& [u, w] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
    if (n.dot((w - u).cross(x - u)) < -slack * (w - u).norm()) return std::nullopt;
  return x;
}

/// The deepest point of one solid's surface inside another solid, found from seeds: a point of
/// the surface, the triangle it lies on, and for a point where the two surfaces cross, the
/// direction along the triangle that leads into the other solid.
struct SurfaceDepth {
  const Surface& surface;
  const Solid& other;
  double best = 0;
  int inside = 0;  // seeds inside the other
  struct Seed {
    Eigen::Vector3d p;
    int tri;
    double depth;
  };
  std::vector<Seed> seeds;

  /// The depth of p in the other solid; 0 when it is not deeper than `floor`.
  double depth_at(const Eigen::Vector3d& p, double floor = kTouchTolerance) const {
    return std::max(0.0, other.depth_of(p, floor));
  }

  void seed(const Eigen::Vector3d& p, int tri) {
    double d = depth_at(p);
    best = std::max(best, d);
    seeds.push_back({p, tri, d});
    inside += d > 0;
  }

  /// From a point where the surfaces cross, along `dir` in the triangle: steps growing from a
  /// micrometre to the triangle's size (the overlap may be a sliver or a slab).
  void along(const Eigen::Vector3d& p, int tri, const Eigen::Vector3d& dir) {
    // Enough points inside to start the search for the deepest from: a deep overlap crosses at
    // thousands of triangle pairs.
    if (inside >= 32) return;
    const double size = surface.box(tri).diagonal().norm();
    double last = -1;
    for (double step = 1e-6; step <= size; step *= 2) {
      Eigen::Vector3d q = p + step * dir;
      if (!surface.covers(tri, q, 0)) break;
      // Within a thousandth of the step from a mesh's surface: running along it, they touch here.
      const double gap = other.mesh_gap(q);
      if (gap >= 0 && gap < 1e-3 * step) break;
      double d = gap < 0 ? depth_at(q) : gap > kTouchTolerance && other.contains(q) ? gap : 0;
      if (d > 0) {
        seeds.push_back({q, tri, d});
        ++inside;
      }
      best = std::max(best, d);
      // Past the deepest point on this line; or still not inside 1 mm from a crossing: the
      // surfaces only touch here (where they cross, even at 1 degree, the depth grows from the
      // first steps).
      if (d < last || (d == 0 && step >= 1e-3)) break;
      last = d;
    }
  }

  /// Pattern search on the triangle from the deepest seeds: the deepest point near each.
  void polish(size_t count) {
    std::sort(seeds.begin(), seeds.end(), [](const Seed& a, const Seed& b) { return a.depth > b.depth; });
    for (size_t k = 0; k < std::min(count, seeds.size()) && seeds[k].depth > 0; ++k) {
      Seed s = seeds[k];
      Eigen::Vector3d dirs[3];
      for (int e = 0; e < 3; ++e) dirs[e] = (surface.corner(s.tri, (e + 1) % 3) - surface.corner(s.tri, e)).normalized();
      // A move must gain more than rounding: on a plateau (a face parallel to the triangle, far
      // from the origin) noise alone would walk the point in 0.1 um steps for ever.
      int moves = 0;
      for (double h = surface.box(s.tri).diagonal().norm() / 4; h > 1e-7 && moves < 500;) {
        bool moved = false;
        for (int e = 0; e < 6 && !moved; ++e) {
          Eigen::Vector3d q = s.p + (e < 3 ? h : -h) * dirs[e % 3];
          if (!surface.covers(s.tri, q, 0)) continue;
          double d = depth_at(q, s.depth);
          if (d > s.depth + 1e-3 * h) {
            ++moves;
            s = {q, s.tri, d};
            moved = true;
          }
        }
        if (!moved) h /= 2;
      }
      best = std::max(best, s.depth);
    }
  }
};

/// Solids whose surfaces coincide (a pallet placed twice, an array of pitch 0, a box exactly
/// on a block) have no point of one surface inside the other: their overlap is inside both. From
/// the centres of (up to 64, spread) triangles of `surface` that lie on or in `other`, steps
/// inward along the triangle's normal; returns the deepest point inside both found: its
/// distance to the nearer of the two surfaces (0 when they only touch). Stops at the first point
/// deeper than `enough`.
double common_depth(const Surface& surface, const Solid& own, const Solid& other, const std::vector<int>& tris, double enough) {
  // A point's depth in both: the cheaper solid (a primitive) asked first, the other only when
  // the point is inside the first.
  const bool swap = own.shape.kind == Shape::Kind::Mesh && other.shape.kind != Shape::Kind::Mesh;
  const Solid &first = swap ? other : own, &second = swap ? own : other;
  auto inside_both = [&](const Eigen::Vector3d& p) {
    const double d = std::max(0.0, first.depth_of(p));
    return d == 0 ? 0.0 : std::min(d, std::max(0.0, second.depth_of(p)));
  };
  double best = 0;
  const size_t stride = std::max<size_t>(1, tris.size() / 64);
  for (size_t k = 0; k < tris.size(); k += stride) {
    const int t = tris[k];
    const Eigen::Vector3d c = (surface.corner(t, 0) + surface.corner(t, 1) + surface.corner(t, 2)) / 3;
    const double gap = other.mesh_gap(c);  // -1: a primitive
    const bool on_or_in = gap >= 0 ? gap <= kTouchTolerance || other.contains(c) : other.depth_of(c) > -kTouchTolerance;
    if (!on_or_in) continue;  // outside the other: nothing common here
    const Eigen::Vector3d inward = -surface.normal(t).normalized();
    const double size = surface.box(t).diagonal().norm() + 1;
    double last = -1;
    for (double step = 1e-6; step <= size; step *= 2) {
      const Eigen::Vector3d p = c + step * inward;
      const double d = inside_both(p);
      best = std::max(best, d);
      if (best > enough) return best;
      if (d < last || (d == 0 && step >= 1e-3)) break;
      last = d;
    }
  }
  return best;
}

/// How deep two solids (closed meshes or primitives) overlap: the deepest point of either
/// surface inside the other solid, its distance to that solid's surface; 0 when they only touch.
/// FCL checks meshes as surfaces and its depths for meshes are per triangle pair, so the depth
/// is measured here. Candidates: every vertex of one inside the other, and where the two
/// surfaces cross, points leading from the crossing into the other solid (a face pushed into a
/// solid has its vertices outside: pallets side by side too close, a drum half into a rack).
/// An open mesh is a surface: only its points inside the other count (`a_solid`, `b_solid`).
/// `enough`: a depth beyond which the caller needs no more (a collision is a collision): the
/// search stops at the first point deeper, and returns that depth, a lower bound of the deepest.
double solid_overlap_depth(const fcl::CollisionObjectd* a, const fcl::CollisionObjectd* b, bool a_solid, bool b_solid,
                           double enough = INFINITY) {
  const Surface sa(a), sb(b);
  const Solid solid_a(a), solid_b(b);
  SurfaceDepth in_b{sa, solid_b, 0, 0, {}}, in_a{sb, solid_a, 0, 0, {}};
  const fcl::AABBd &ba = a->getAABB(), &bb = b->getAABB();
  auto near = [](const fcl::AABBd& box, const Eigen::Vector3d& p) {
    return (p.array() >= box.min_.array() - kTouchTolerance).all() && (p.array() <= box.max_.array() + kTouchTolerance).all();
  };
  auto near_box = [](const fcl::AABBd& box, const Eigen::AlignedBox3d& t) {
    return (t.min().array() <= box.max_.array() + kTouchTolerance).all() && (t.max().array() >= box.min_.array() - kTouchTolerance).all();
  };
  // How deep the points found so far are, counting only the solid sides.
  auto found = [&] { return std::max(b_solid ? in_b.best : 0.0, a_solid ? in_a.best : 0.0); };
  // Triangles of each surface within the other's bounds, with their vertices as seeds.
  auto candidates = [&](const Surface& s, const fcl::AABBd& other_box, SurfaceDepth& depth) {
    std::vector<int> out;
    for (int k = 0; k < static_cast<int>(s.t.size()) && found() <= enough; ++k) {
      if (!near_box(other_box, s.box(k))) continue;
      out.push_back(k);
      for (int c = 0; c < 3; ++c)
        if (near(other_box, s.corner(k, c))) depth.seed(s.corner(k, c), k);
      depth.seed((s.corner(k, 0) + s.corner(k, 1) + s.corner(k, 2)) / 3, k);
    }
    return out;
  };
  const std::vector<int> ta = candidates(sa, bb, in_b);
  if (found() > enough) return found();
  const std::vector<int> tb = candidates(sb, ba, in_a);
  if (found() > enough) return found();
  // Where the surfaces cross: each pair of triangles whose bounds meet.
  std::vector<Eigen::AlignedBox3d> boxes_b;
  for (int j : tb) boxes_b.push_back(sb.box(j));
  for (int i : ta) {
    if (found() > enough) return found();
    const Eigen::AlignedBox3d box_i = sa.box(i);
    const Eigen::Vector3d na = sa.normal(i).normalized();
    for (size_t jj = 0; jj < tb.size(); ++jj) {
      if (!box_i.intersects(boxes_b[jj])) continue;
      const int j = tb[jj];
      const Eigen::Vector3d nb = sb.normal(j).normalized();
      if (na.cross(nb).norm() < 1e-9) continue;  // parallel faces: touching or covered by the seeds
      std::vector<Eigen::Vector3d> points;
      for (int e = 0; e < 3; ++e) {
        if (auto x = segment_crossing(sa.corner(i, e), sa.corner(i, (e + 1) % 3), sb.corner(j, 0), sb.corner(j, 1), sb.corner(j, 2)))
          points.push_back(*x);
        if (auto x = segment_crossing(sb.corner(j, e), sb.corner(j, (e + 1) % 3), sa.corner(i, 0), sa.corner(i, 1), sa.corner(i, 2)))
          points.push_back(*x);
      }
      if (points.empty()) continue;
      Eigen::Vector3d mid = Eigen::Vector3d::Zero();
      for (const Eigen::Vector3d& p : points) mid += p;
      mid /= static_cast<double>(points.size());
      // Into the other solid along each triangle: against the other's outward normal, in the plane.
      const Eigen::Vector3d into_b = -(nb - nb.dot(na) * na).normalized(), into_a = -(na - na.dot(nb) * nb).normalized();
      in_b.along(mid, i, into_b);
      in_a.along(mid, j, into_a);
    }
  }
  if (found() > enough) return found();
  double depth = 0;
  if (a_solid && b_solid)
    depth = std::max(common_depth(sa, solid_a, solid_b, ta, enough), common_depth(sb, solid_b, solid_a, tb, enough));
  if (b_solid) {
    in_b.polish(4);
    depth = std::max(depth, in_b.best);
  }
  if (a_solid) {
    in_a.polish(4);
    depth = std::max(depth, in_a.best);
  }
  return depth > kTouchTolerance ? depth : 0;
}

/// Whether one of two shapes that do not intersect lies wholly inside the other, a closed mesh:
/// one point of the inner shape decides (its centre; a mesh's first vertex).
bool contained_in_closed_mesh(const fcl::CollisionObjectd* outer, const fcl::CollisionObjectd* inner) {
  if (!closed_mesh(shape_of(outer)) || !outer->getAABB().contain(inner->getAABB())) return false;
  const Shape& si = shape_of(inner);
  Eigen::Vector3d p_inner = si.kind == Shape::Kind::Mesh ? Eigen::Vector3d(si.mesh->vertices[0].cwiseProduct(si.scale))
                                                         : Eigen::Vector3d::Zero();
  return Solid(outer).contains(Eigen::Isometry3d(inner->getTransform()) * p_inner);
}

/// The depth of a collision FCL found between two shapes, with closed meshes as solids.
double contact_depth(const fcl::CollisionObjectd* a, const fcl::CollisionObjectd* b, const fcl::CollisionResultd& res,
                     double enough) {
  const Shape &A = shape_of(a), &B = shape_of(b);
  // Boxes, cylinders and spheres: the exact shortest separating push (FCL's EPA said a drum
  // standing in an overpack overlapped it by its height, 0.851 m, for a 0.6415 m push sideways).
  if (is_primitive(A) && is_primitive(B))
    return primitive_penetration_depth(A, Eigen::Isometry3d(a->getTransform()), B, Eigen::Isometry3d(b->getTransform()));
  const bool a_solid = A.kind != Shape::Kind::Mesh || closed_mesh(A);
  const bool b_solid = B.kind != Shape::Kind::Mesh || closed_mesh(B);
  double depth = 0;
  if (closed_mesh(A) || closed_mesh(B)) {
    if (a_solid && b_solid) return solid_overlap_depth(a, b, true, true, enough);
    // A surface against a solid: FCL's depth of the crossing, or how deep the surface lies inside.
    depth = solid_overlap_depth(a, b, a_solid, b_solid, enough);
  }
  for (size_t k = 0; k < res.numContacts(); ++k) depth = std::max(depth, res.getContact(k).penetration_depth);
  // A contact without depth (two open surfaces) still is a collision: count it as touching.
  return std::max(depth, 0.0);
}

/// Penetration depth of two placed shapes: > 0 when they interpenetrate, 0 when apart or touching.
/// A shape wholly inside a closed mesh interpenetrates it by its distance to the mesh's surface.
/// Beyond `enough` the depth may be a lower bound (closed meshes: the search stops there).
double penetration(const fcl::CollisionObjectd* a, const fcl::CollisionObjectd* b, double enough = INFINITY) {
  fcl::CollisionRequestd req(1, /*enable_contact=*/true);
  fcl::CollisionResultd res;
  if (fcl::collide(a, b, req, res) != 0) return contact_depth(a, b, res, enough);
  if (!contained_in_closed_mesh(a, b) && !contained_in_closed_mesh(b, a)) return 0;
  fcl::DistanceRequestd dreq(false, false, 1e-9, 1e-9, 1e-9, fcl::GST_INDEP);
  fcl::DistanceResultd dres;
  fcl::distance(a, b, dreq, dres);
  return std::max(dres.min_distance, 0.0);
}

/// Signed distance between two placed shapes: minus the penetration depth when they collide, or
/// when one lies wholly inside the other, a closed mesh (minus its distance to the surface).
/// The distance query first: apart is the common case, and only contact needs the depth.
double signed_distance(const fcl::CollisionObjectd* a, const fcl::CollisionObjectd* b) {
  // The independent GJK with a tight tolerance: libccd's default is off by centimetres on rotated boxes.
  fcl::DistanceRequestd dreq(false, false, 1e-9, 1e-9, 1e-9, fcl::GST_INDEP);
  fcl::DistanceResultd dres;
  fcl::distance(a, b, dreq, dres);
  if (dres.min_distance > 0)
    return contained_in_closed_mesh(a, b) || contained_in_closed_mesh(b, a) ? -dres.min_distance : dres.min_distance;
  // In contact (FCL answers 0 or -1): the depth from the collision query, 0 when only touching.
  fcl::CollisionRequestd creq(1, /*enable_contact=*/true);
  fcl::CollisionResultd cres;
  if (fcl::collide(a, b, creq, cres) == 0) return 0;
  return -contact_depth(a, b, cres, INFINITY);
}

/// The queries ContactMemo remembers.
enum class PairQuery : uint64_t { Penetration = 1, SignedDistance = 2 };

/// A pair query's answer from `memo` when it involves a closed mesh (what costs): remembered, or
/// computed by `query` and remembered. Other pairs (and a null memo) are computed each time.
template <class Query>
double remembered(ContactMemo* memo, PairQuery kind, const fcl::CollisionObjectd* a, const fcl::CollisionObjectd* b,
                  double enough, Query query) {
  const Shape &A = shape_of(a), &B = shape_of(b);
  if (!memo || !(closed_mesh(A) || closed_mesh(B))) return query();
  ContactMemo::Key key{};
  size_t n = 0;
  auto put = [&](double x) { key[n++] = std::bit_cast<uint64_t>(x); };
  key[n++] = static_cast<uint64_t>(kind);
  put(enough);
  for (const fcl::CollisionObjectd* o : {a, b}) {
    const Shape& s = shape_of(o);
    key[n++] = static_cast<uint64_t>(s.kind) | (s.mesh && s.mesh->closed ? 16u : 0u);
    key[n++] = reinterpret_cast<uintptr_t>(s.mesh.get());
    for (double x : {s.box_size.x(), s.box_size.y(), s.box_size.z(), s.radius, s.length, s.scale.x(), s.scale.y(), s.scale.z()})
      put(x);
    const fcl::Transform3d& X = o->getTransform();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) put(X(r, c));
  }
  if (std::optional<double> known = memo->find(key)) return *known;
  const double answer = query();
  memo->store(key, answer, A.mesh, B.mesh);
  return answer;
}

/// How far any point of a placed shape has moved since it was at `X_then`: the displacement of
/// its origin plus the turn (rad) times the farthest the shape reaches from its origin.
/// How far any point within `reach` of a frame can have moved when the frame went from `from`
/// to `to`: its displacement plus its turn times the reach.
double moved(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to, double reach) {
  if (to.linear() == from.linear()) return (to.translation() - from.translation()).norm();  // not turned (most shapes)
  const double turn = Eigen::AngleAxisd(to.linear() * from.linear().transpose()).angle();
  return (to.translation() - from.translation()).norm() + (turn > 0 ? turn * reach : 0.0);
}

double travel(const fcl::CollisionObjectd& shape, const fcl::Transform3d& X_then) {
  const fcl::CollisionGeometryd& g = *shape.collisionGeometry();
  return moved(X_then, shape.getTransform(), g.aabb_center.norm() + g.aabb_radius);
}

/// Distance between two axis-aligned boxes (0 when they overlap).
double box_gap(const fcl::AABBd& a, const fcl::AABBd& b) {
  Eigen::Vector3d gap = (a.min_ - b.max_).cwiseMax(b.min_ - a.max_).cwiseMax(0.0);
  return gap.norm();
}

}  // namespace

size_t ContactMemo::KeyHash::operator()(const Key& k) const {
  uint64_t h = 0x9e3779b97f4a7c15ull;
  for (uint64_t w : k) {
    h ^= w + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h *= 0xff51afd7ed558ccdull;
  }
  return static_cast<size_t>(h ^ (h >> 33));
}

std::optional<double> ContactMemo::find(const Key& key) {
  auto it = answers_.find(key);
  if (it == answers_.end()) return std::nullopt;
  ++hits_;
  return it->second;
}

void ContactMemo::store(const Key& key, double answer, const std::shared_ptr<const TriangleMesh>& a,
                        const std::shared_ptr<const TriangleMesh>& b) {
  if (answers_.size() >= kCapacity) {
    answers_.clear();
    meshes_.clear();
  }
  answers_.emplace(key, answer);
  for (const auto& m : {a, b})
    if (m) meshes_.emplace(m.get(), m);
}

struct CollisionWorld::Impl {
  const GeometryModel& geometry;
  ContactMemo* memo = geometry.contacts.get();
  // Per object, its shapes as FCL objects in world placement. Built on first use.
  std::map<int, std::vector<std::unique_ptr<fcl::CollisionObjectd>>> parts;
  // FCL geometry per shape (device parts are placed anew for each configuration).
  std::unordered_map<const Shape*, std::shared_ptr<fcl::CollisionGeometryd>> shapes;
  // Every object's bounds where it is now (by object: a proximity query looks at every object's,
  // a hashed lookup each was a twentieth of a fast run); filled on first use.
  std::vector<fcl::AABBd> boxes;
  // proximity(): the last distance measured per shape pair (object, other, shape, other's
  // shape), with both shapes' placements then.
  struct Measured {
    double distance;
    fcl::Transform3d X_a, X_b;
  };
  struct MeasuredKey {
    int object, other;
    uint32_t shape, other_shape;
    bool operator==(const MeasuredKey&) const = default;
  };
  struct MeasuredHash {
    size_t operator()(const MeasuredKey& k) const {
      const uint64_t a = (static_cast<uint64_t>(static_cast<uint32_t>(k.object)) << 32) | static_cast<uint32_t>(k.other);
      const uint64_t b = (static_cast<uint64_t>(k.shape) << 32) | k.other_shape;
      return std::hash<uint64_t>{}(a * 0x9e3779b97f4a7c15ull ^ (b + 0x632be59bd9b4e019ull + (a << 6) + (a >> 2)));
    }
  };
  // Looked up once per shape pair a proximity query considers: hashed (an ordered map of tuples
  // was a tenth of the receiving campaign's time).
  std::unordered_map<MeasuredKey, Measured, MeasuredHash> measured;
  /// Per object, how many times one of its shapes was placed anew: what a search remembers.
  std::vector<uint64_t> moves;
  /// nearest()'s last search per (object, other): the objects' moves then, the parts asked for,
  /// the limit, and the nearest shapes found below it (exact: every pair that could be nearer
  /// was measured), or none.
  struct Searched {
    bool valid = false;
    uint64_t moves[2] = {0, 0};
    std::vector<char> parts;
    double limit = 0;
    std::optional<Proximity> found;
  };
  std::unordered_map<uint64_t, Searched> searched;

  const fcl::AABBd& bounds(int object) {
    if (boxes.empty())
      for (const ObjectGeometry& g : geometry.objects) boxes.emplace_back(g.bbox_world.min(), g.bbox_world.max());
    return boxes[object];
  }
  uint64_t moves_of(int object) const { return static_cast<size_t>(object) < moves.size() ? moves[object] : 0; }

  /// The nearest shapes of `object` (its `parts`, when given) and `other` at their placements,
  /// when nearer than `limit`. Branch and bound: shape pairs in order of a lower bound of their
  /// distance, until no bound is below the nearest pair found. The bound: their boxes' gap when
  /// apart, or the distance measured last time less how far either shape has moved since
  /// (conservative advancement).
  std::optional<Proximity> nearest(int object, int other, double limit, const std::vector<char>& parts) {
    const auto& mine = of(object);
    const auto& theirs = of(other);
    // Neither moved since the pair was last searched (a crane standing by a rack at each sample
    // while the forklift works): that search's answer holds, as far as it reached.
    const uint64_t pair_key = (static_cast<uint64_t>(static_cast<uint32_t>(object)) << 32) | static_cast<uint32_t>(other);
    Searched& last_search = searched[pair_key];
    const uint64_t moves_now[2] = {moves_of(object), moves_of(other)};
    if (last_search.valid && last_search.moves[0] == moves_now[0] && last_search.moves[1] == moves_now[1] && last_search.parts == parts) {
      // Found below its limit, the nearest shapes then were exact (every pair that could be
      // nearer was measured), and are now; else nothing was nearer than that limit.
      if (last_search.found && last_search.found->distance < last_search.limit) return last_search.found;
      if (limit <= last_search.limit) return std::nullopt;
    }
    std::optional<Proximity> best = search(object, other, limit, parts, mine, theirs);
    last_search.valid = true;
    last_search.moves[0] = moves_now[0];
    last_search.moves[1] = moves_now[1];
    if (last_search.parts != parts) last_search.parts = parts;  // (no allocation a search)
    last_search.limit = limit;
    last_search.found = best;
    return best;
  }

  /// nearest()'s search itself.
  std::optional<Proximity> search(int object, int other, double limit, const std::vector<char>& parts,
                                  const std::vector<std::unique_ptr<fcl::CollisionObjectd>>& mine,
                                  const std::vector<std::unique_ptr<fcl::CollisionObjectd>>& theirs) {
    const auto& objects = geometry.objects;
    std::vector<std::tuple<double, size_t, size_t>> pairs;
    for (size_t i = 0; i < mine.size(); ++i)
      for (size_t k = 0; k < theirs.size(); ++k) {
        int part = objects[object].shapes[i].part;
        if (!parts.empty() && (part < 0 || !parts[part])) continue;
        double bound = box_gap(mine[i]->getAABB(), theirs[k]->getAABB());
        if (bound == 0) bound = -INFINITY;  // overlapping boxes: any depth
        if (bound >= limit) continue;  // what was measured before only raises the bound
        auto last = measured.find({object, other, static_cast<uint32_t>(i), static_cast<uint32_t>(k)});
        if (last != measured.end())
          bound = std::max(bound, last->second.distance - travel(*mine[i], last->second.X_a) - travel(*theirs[k], last->second.X_b));
        if (bound < limit) pairs.emplace_back(bound, i, k);
      }
    std::sort(pairs.begin(), pairs.end());
    std::optional<Proximity> best;
    for (auto [bound, i, k] : pairs) {
      if (best && bound >= best->distance) break;
      double d = signed_distance(mine[i].get(), theirs[k].get());
      measured[{object, other, static_cast<uint32_t>(i), static_cast<uint32_t>(k)}] = {d, mine[i]->getTransform(), theirs[k]->getTransform()};
      if (!best || d < best->distance) {
        best = Proximity{other, objects[object].shapes[i].part, objects[other].shapes[k].part, d};
        best->shape = static_cast<int>(i);
        best->other_shape = static_cast<int>(k);
      }
    }
    return best;
  }

  /// The farthest any point of `object`'s shapes (of device part `part`) lies from the frame
  /// they move with (the part's, or the object's), computed once.
  double reach(int object, int part) {
    auto [it, fresh] = reaches.try_emplace((static_cast<int64_t>(object) << 20) + part + 1, 0.0);
    if (!fresh) return it->second;
    const ObjectGeometry& g = geometry.objects[object];
    const auto& list = of(object);
    for (size_t k = 0; k < g.shapes.size() && k < list.size(); ++k) {
      const Shape& s = g.shapes[k];
      if (s.part != part) continue;
      const Eigen::Isometry3d X_frame_shape =
          part >= 0 ? g.X_object_part[part].inverse() * s.X_object_shape : s.X_object_shape;
      const fcl::CollisionGeometryd& c = *list[k]->collisionGeometry();
      it->second = std::max(it->second, X_frame_shape.translation().norm() + c.aabb_center.norm() + c.aabb_radius);
    }
    return it->second;
  }
  std::unordered_map<int64_t, double> reaches;  ///< by (object << 20) + part + 1

  /// A device's shapes in the frames of their parts, computed once (placing a crane's parts
  /// thousands of times a run inverted each part's pose as often).
  const std::vector<Eigen::Isometry3d>& in_parts(int object) {
    auto [it, fresh] = part_shapes.try_emplace(object);
    if (fresh) {
      const ObjectGeometry& g = geometry.objects[object];
      for (const Shape& s : g.shapes) it->second.push_back(g.X_object_part[s.part].inverse() * s.X_object_shape);
    }
    return it->second;
  }
  std::unordered_map<int, std::vector<Eigen::Isometry3d>> part_shapes;
  /// A device's parts where move_parts last placed them (none once placed otherwise): the shapes
  /// of a part still there are where they were (a crane's runway at each of 3,300 samples).
  std::unordered_map<int, std::vector<Eigen::Isometry3d>> parts_at;
  std::vector<Eigen::Isometry3d> scratch;  ///< shapes' poses being placed

  void place(int object, const std::vector<Eigen::Isometry3d>& X_world_shape) {
    place(object, [&](size_t k) { return &X_world_shape[k]; });
    parts_at.erase(object);
  }
  /// Places each shape k of `object` at *at(k), or leaves it where it is when at(k) is null.
  template <class At>
  void place(int object, At at) {
    auto& list = of(object);
    fcl::AABBd box;
    bool moved_any = false;
    for (size_t k = 0; k < list.size(); ++k) {
      const Eigen::Isometry3d* X = at(k);
      if (X && !(list[k]->getTransform().matrix() == X->matrix())) {  // a crane's runway stays where it is
        list[k]->setTransform(fcl::Transform3d(X->matrix()));
        list[k]->computeAABB();
        moved_any = true;
      }
      if (k == 0) box = list[k]->getAABB();
      else box += list[k]->getAABB();
    }
    if (moves.empty()) moves.resize(geometry.objects.size(), 0);
    if (!list.empty()) {
      bounds(object);  // (filled)
      boxes[object] = box;
    }
    if (moved_any) ++moves[object];
  }

  std::shared_ptr<fcl::CollisionGeometryd> geometry_of(const Shape& s) {
    auto& g = shapes[&s];
    if (!g) g = make_geometry(s);
    return g;
  }

  const std::vector<std::unique_ptr<fcl::CollisionObjectd>>& of(int object) {
    auto it = parts.find(object);
    if (it != parts.end()) return it->second;
    auto& list = parts[object];
    const ObjectGeometry& g = geometry.objects[object];
    for (const Shape& s : g.shapes) {
      Eigen::Isometry3d X = g.X_world_object * s.X_object_shape;
      auto obj = std::make_unique<fcl::CollisionObjectd>(geometry_of(s), fcl::Transform3d(X.matrix()));
      obj->setUserData(const_cast<Shape*>(&s));  // read back by shape_of()
      obj->computeAABB();
      list.push_back(std::move(obj));
    }
    return list;
  }

  /// A device's shapes placed at per-part world poses, each with its part index.
  std::vector<std::pair<int, std::unique_ptr<fcl::CollisionObjectd>>> placed(const Device& d,
                                                                             const std::vector<Eigen::Isometry3d>& X) {
    std::vector<std::pair<int, std::unique_ptr<fcl::CollisionObjectd>>> out;
    for (size_t p = 0; p < d.parts.size(); ++p)
      for (const Shape& s : d.parts[p].shapes) {
        Eigen::Isometry3d Xs = X[p] * s.X_object_shape;
        auto obj = std::make_unique<fcl::CollisionObjectd>(geometry_of(s), fcl::Transform3d(Xs.matrix()));
        obj->setUserData(const_cast<Shape*>(&s));  // read back by shape_of()
        obj->computeAABB();
        out.emplace_back(static_cast<int>(p), std::move(obj));
      }
    return out;
  }

  /// The deepest collision between non-adjacent parts among `shapes`.
  std::vector<Collision> self(const Device& d, const std::vector<std::pair<int, std::unique_ptr<fcl::CollisionObjectd>>>& shapes,
                              bool all) {
    std::vector<Collision> found;
    for (size_t i = 0; i < shapes.size(); ++i)
      for (size_t k = i + 1; k < shapes.size(); ++k) {
        int a = shapes[i].first, b = shapes[k].first;
        if (a == b || d.may_touch(a, b)) continue;
        if (!shapes[i].second->getAABB().overlap(shapes[k].second->getAABB())) continue;
        double depth = remembered(memo, PairQuery::Penetration, shapes[i].second.get(), shapes[k].second.get(), INFINITY,
                                  [&] { return penetration(shapes[i].second.get(), shapes[k].second.get()); });
        if (depth <= kTouchTolerance) continue;
        auto same = std::find_if(found.begin(), found.end(), [&](const Collision& c) {
          return c.part == std::min(a, b) && c.other_part == std::max(a, b);
        });
        if (same != found.end()) {
          same->depth = std::max(same->depth, depth);
        } else {
          found.push_back({-1, std::min(a, b), std::max(a, b), depth});
          if (!all) return found;
        }
      }
    return found;
  }
};

CollisionWorld::CollisionWorld(const GeometryModel& geometry) : impl_(std::make_unique<Impl>(Impl{geometry, geometry.contacts.get(), {}, {}, {}, {}, {}, {}, {}, {}, {}, {}})) {}
CollisionWorld::~CollisionWorld() = default;

std::optional<double> CollisionWorld::distance(int a, int b, std::pair<int, int>* nearest_parts) {
  const auto& pa = impl_->of(a);
  const auto& pb = impl_->of(b);
  if (pa.empty() || pb.empty()) return std::nullopt;
  double best = INFINITY;
  for (size_t i = 0; i < pa.size(); ++i)
    for (size_t k = 0; k < pb.size(); ++k) {
      const double d = remembered(impl_->memo, PairQuery::SignedDistance, pa[i].get(), pb[k].get(), INFINITY,
                                  [&] { return signed_distance(pa[i].get(), pb[k].get()); });
      if (d >= best) continue;
      best = d;
      if (nearest_parts) *nearest_parts = {impl_->geometry.objects[a].shapes[i].part, impl_->geometry.objects[b].shapes[k].part};
    }
  return best;
}

double CollisionWorld::depth_inside(int object, const Eigen::Vector3d& p_world) {
  double depth = 0;
  for (const auto& x : impl_->of(object)) {
    const Shape& s = shape_of(x.get());
    if (s.kind == Shape::Kind::Mesh && !s.mesh->closed) continue;
    depth = std::max(depth, Solid(x.get()).depth_of(p_world));
  }
  return depth;
}

std::optional<double> CollisionWorld::distance_to_point(int object, const Eigen::Vector3d& p_world) {
  const auto& shapes = impl_->of(object);
  if (shapes.empty()) return std::nullopt;
  if (depth_inside(object, p_world) > 0) return 0.0;
  fcl::Transform3d X = fcl::Transform3d::Identity();
  X.translation() = p_world;
  constexpr double kPoint = 1e-9;  // a sphere this small stands for the point
  fcl::CollisionObjectd point(std::make_shared<fcl::Sphered>(kPoint), X);
  point.computeAABB();
  double best = INFINITY;
  for (const auto& x : shapes) {
    fcl::DistanceRequestd req(false, false, 1e-9, 1e-9, 1e-9, fcl::GST_INDEP);
    fcl::DistanceResultd res;
    fcl::distance(x.get(), &point, req, res);
    best = std::min(best, std::max(res.min_distance + kPoint, 0.0));
  }
  return best;
}

std::vector<Collision> CollisionWorld::self_collisions(int object) {
  const ObjectGeometry& g = impl_->geometry.objects[object];
  if (!g.device) return {};
  std::vector<Eigen::Isometry3d> world(g.device->parts.size());
  for (size_t p = 0; p < world.size(); ++p) world[p] = g.X_world_object * g.X_object_part[p];
  auto shapes = impl_->placed(*g.device, world);
  return impl_->self(*g.device, shapes, true);
}

std::optional<Collision> CollisionWorld::device_collision(int object, const std::vector<Eigen::Isometry3d>& X_world_part,
                                                          const std::vector<int>& ignore, int target,
                                                          const std::vector<char>& tool_parts, const std::vector<int>& stands_on,
                                                          bool first, const std::vector<char>& only) {
  const ObjectGeometry& g = impl_->geometry.objects[object];
  if (!g.device) return std::nullopt;
  const std::vector<char> moved = stands_on.empty() ? std::vector<char>() : g.device->moved_parts();
  auto shapes = impl_->placed(*g.device, X_world_part);
  if (!only.empty())
    std::erase_if(shapes, [&](const auto& placed) { return !only[placed.first]; });
  std::optional<Collision> deepest;
  auto note = [&](const Collision& c) {
    if (!deepest || c.depth > deepest->depth) deepest = c;
  };
  for (const Collision& c : impl_->self(*g.device, shapes, false)) note(c);
  fcl::AABBd box;
  bool any = false;
  for (const auto& [p, s] : shapes) {
    if (!any) box = s->getAABB();
    else box += s->getAABB();
    any = true;
  }
  if (!any) return deepest;
  const auto& objects = impl_->geometry.objects;
  for (size_t o = 0; o < objects.size(); ++o) {
    int other = static_cast<int>(o);
    // Where the object is now (a load a run's planning set down elsewhere), not where the vault has it.
    if (other == object || objects[o].shapes.empty() || box_gap(box, impl_->bounds(other)) > kTouchTolerance) continue;
    if (std::find(ignore.begin(), ignore.end(), other) != ignore.end()) continue;
    const bool support = std::find(stands_on.begin(), stands_on.end(), other) != stands_on.end();
    const auto& theirs = impl_->of(other);
    const fcl::AABBd& bounds = impl_->bounds(other);
    for (const auto& [p, s] : shapes) {
      if (support && !moved[p]) continue;  // the base on its pedestal
      // (A crane's bridge spans the hall: its box meets every object's, a hook's few.)
      if (box_gap(s->getAABB(), bounds) > kTouchTolerance) continue;
      for (size_t k = 0; k < theirs.size(); ++k) {
        // The tool's parts may touch the target, as a run's move_to lets them (kTargetTouch), but
        // not enter it: a gripper buried in its drum is a collision.
        const bool touches = other == target && p < static_cast<int>(tool_parts.size()) && tool_parts[p];
        if (!s->getAABB().overlap(theirs[k]->getAABB())) continue;
        const double limit = touches ? kTargetTouch : kTouchTolerance;
        const double enough = first ? limit : INFINITY;
        const fcl::CollisionObjectd *mine = s.get(), *other_shape = theirs[k].get();  // (clang 15 captures no structured binding)
        double depth = remembered(impl_->memo, PairQuery::Penetration, mine, other_shape, enough,
                                  [&] { return penetration(mine, other_shape, enough); });
        if (depth > limit) {
          int other_part = objects[o].shapes[k].part;
          note({other, p, other_part, depth});
        }
      }
    }
  }
  return deepest;
}

namespace {

/// The lowest and highest z of the part of a shape (placed in the world) that lies over the
/// rectangle `plan` (xy), or nullopt when none does. Spheres exactly; other shapes as triangles
/// clipped to the rectangle (cylinders as the 32-sided prism around them: never shallower).
std::optional<std::pair<double, double>> z_over(const Shape& shape, const Eigen::Isometry3d& X_world_shape,
                                                const Eigen::AlignedBox2d& plan) {
  if (shape.kind == Shape::Kind::Sphere) {
    const Eigen::Vector3d c = X_world_shape.translation();
    const Eigen::Vector2d nearest = c.head<2>().cwiseMax(plan.min()).cwiseMin(plan.max());
    const double d = (nearest - c.head<2>()).norm();
    if (d > shape.radius) return std::nullopt;
    const double h = std::sqrt(shape.radius * shape.radius - d * d);
    return std::pair{c.z() - h, c.z() + h};
  }
  Shape placed = shape;
  placed.X_object_shape = X_world_shape;
  if (placed.kind == Shape::Kind::Cylinder) placed.radius /= std::cos(std::numbers::pi / 32);
  const TriangleMesh m = tessellate(placed);
  std::optional<std::pair<double, double>> range;
  std::vector<Eigen::Vector3d> poly, next;
  for (const Eigen::Vector3i& t : m.triangles) {
    poly = {m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]};
    // Sutherland-Hodgman against the rectangle's four sides.
    for (int side = 0; side < 4 && !poly.empty(); ++side) {
      const int axis = side / 2;
      const double bound = side % 2 ? plan.max()[axis] : plan.min()[axis];
      auto inside = [&](const Eigen::Vector3d& p) { return side % 2 ? p[axis] <= bound : p[axis] >= bound; };
      next.clear();
      for (size_t i = 0; i < poly.size(); ++i) {
        const Eigen::Vector3d &p = poly[i], &q = poly[(i + 1) % poly.size()];
        if (inside(p)) next.push_back(p);
        if (inside(p) != inside(q)) next.push_back(p + (q - p) * ((bound - p[axis]) / (q[axis] - p[axis])));
      }
      poly.swap(next);
    }
    for (const Eigen::Vector3d& v : poly) {
      if (!range) range = std::pair{v.z(), v.z()};
      range->first = std::min(range->first, v.z());
      range->second = std::max(range->second, v.z());
    }
  }
  return range;
}

/// The world boxes of floor blocks, for a quick test before the exact one.
std::vector<Eigen::AlignedBox3d> block_bounds(const std::vector<FloorBlock>& blocks) {
  std::vector<Eigen::AlignedBox3d> out;
  for (const FloorBlock& b : blocks) {
    Shape box;
    box.box_size = b.size;
    out.push_back(shape_bounds(box, b.X_world_centre));
  }
  return out;
}

/// How deep one shape placed at `X` goes into the floors: below the plane at `plane` (its lowest
/// point), or into a block of `blocks` (its exact shape over the block's footprint, clipped).
/// Collision::other is kFloorObject, other_part the container whose floor it is (-1: the plane).
std::optional<Collision> shape_into_floors(const Shape& shape, const Eigen::Isometry3d& X, double plane,
                                           const std::vector<FloorBlock>& blocks, const std::vector<Eigen::AlignedBox3d>& bounds_of) {
  const Eigen::AlignedBox3d bounds = shape_bounds(shape, X);
  std::optional<Collision> here;
  if (const double below = plane - bounds.min().z(); below > kTouchTolerance) here = Collision{kFloorObject, -1, -1, below};
  for (size_t k = 0; k < blocks.size(); ++k) {
    if (!bounds.intersects(bounds_of[k])) continue;
    // How far into the block the shape over its footprint goes, from above or from below, in
    // the block's frame.
    const Eigen::Vector3d half = blocks[k].size / 2;
    auto z = z_over(shape, blocks[k].X_world_centre.inverse() * X, Eigen::AlignedBox2d(-half.head<2>(), half.head<2>()));
    if (!z || z->first >= half.z() || z->second <= -half.z()) continue;
    const double depth = std::min(half.z() - z->first, z->second + half.z());
    if (depth > kTouchTolerance && (!here || depth > here->depth)) here = Collision{kFloorObject, -1, blocks[k].container, depth};
  }
  return here;
}

void keep_deepest(std::optional<Collision>& deepest, const std::optional<Collision>& c) {
  if (c && (!deepest || c->depth > deepest->depth)) deepest = c;
}

}  // namespace

std::optional<Collision> CollisionWorld::into_floors(int object, const std::vector<Eigen::Isometry3d>& X_world_part,
                                                     const std::vector<char>& parts, double plane,
                                                     const std::vector<FloorBlock>& blocks) {
  const ObjectGeometry& g = impl_->geometry.objects[object];
  if (!g.device) return std::nullopt;
  const std::vector<Eigen::AlignedBox3d> bounds_of = block_bounds(blocks);
  std::optional<Collision> deepest;
  for (size_t p = 0; p < g.device->parts.size(); ++p) {
    if (p >= parts.size() || !parts[p]) continue;
    for (const Shape& shape : g.device->parts[p].shapes) {
      std::optional<Collision> here = shape_into_floors(shape, X_world_part[p] * shape.X_object_shape, plane, blocks, bounds_of);
      if (here) here->part = static_cast<int>(p);
      keep_deepest(deepest, here);
    }
  }
  return deepest;
}

std::optional<Collision> CollisionWorld::held_collision(int device, const std::vector<Eigen::Isometry3d>& X_world_part,
                                                        const std::vector<std::pair<int, Eigen::Isometry3d>>& held,
                                                        const std::vector<int>& ignore, int target, const std::vector<char>& tool_parts,
                                                        bool first, double plane, const std::vector<FloorBlock>& blocks) {
  const auto& objects = impl_->geometry.objects;
  // The device's parts but the tool's, where these joint values put them.
  auto parts = impl_->placed(*objects[device].device, X_world_part);
  std::erase_if(parts, [&](const auto& placed) { return placed.first < static_cast<int>(tool_parts.size()) && tool_parts[placed.first]; });
  const std::vector<Eigen::AlignedBox3d> bounds_of = block_bounds(blocks);
  auto is_held = [&](int o) { return std::any_of(held.begin(), held.end(), [&](const auto& h) { return h.first == o; }); };
  std::optional<Collision> deepest;
  for (const auto& carried : held) {
    const int load = carried.first;  // (clang 15 captures no structured binding)
    const Eigen::Isometry3d& X_world_load = carried.second;
    std::vector<std::unique_ptr<fcl::CollisionObjectd>> mine;
    fcl::AABBd box;
    for (const Shape& s : objects[load].shapes) {
      const Eigen::Isometry3d X = X_world_load * s.X_object_shape;
      keep_deepest(deepest, [&] {
        auto c = shape_into_floors(s, X, plane, blocks, bounds_of);
        if (c) c->load = load;
        return c;
      }());
      auto obj = std::make_unique<fcl::CollisionObjectd>(impl_->geometry_of(s), fcl::Transform3d(X.matrix()));
      obj->setUserData(const_cast<Shape*>(&s));  // read back by shape_of()
      obj->computeAABB();
      if (mine.empty()) box = obj->getAABB();
      else box += obj->getAABB();
      mine.push_back(std::move(obj));
    }
    if (mine.empty()) continue;
    auto meet = [&](const fcl::CollisionObjectd* a, const fcl::CollisionObjectd* b, double limit, Collision c) {
      if (!a->getAABB().overlap(b->getAABB())) return;
      const double enough = first ? limit : INFINITY;
      c.depth = remembered(impl_->memo, PairQuery::Penetration, a, b, enough, [&] { return penetration(a, b, enough); });
      if (c.depth > limit) keep_deepest(deepest, c);
    };
    for (const auto& m : mine)
      for (const auto& [p, s] : parts) meet(m.get(), s.get(), kTouchTolerance, Collision{device, -1, p, 0, load});
    for (size_t o = 0; o < objects.size(); ++o) {
      const int other = static_cast<int>(o);
      if (other == device || objects[o].shapes.empty() || is_held(other)) continue;
      if (std::find(ignore.begin(), ignore.end(), other) != ignore.end()) continue;
      if (box_gap(box, impl_->bounds(other)) > kTouchTolerance) continue;
      const auto& theirs = impl_->of(other);
      const double limit = other == target ? kTargetTouch : kTouchTolerance;
      for (const auto& m : mine)
        for (size_t k = 0; k < theirs.size(); ++k) meet(m.get(), theirs[k].get(), limit, Collision{other, -1, objects[o].shapes[k].part, 0, load});
    }
    if (first && deepest) return deepest;
  }
  return deepest;
}

DeviceClearance::DeviceClearance(const Workcell& wc, const GeometryModel& geometry, int device)
    : geometry_(geometry), device_(device) {
  const std::vector<char> is_container = containers(wc);
  for (size_t k = 0; k < wc.objects.size(); ++k) {
    if (static_cast<int>(k) == device) continue;
    if (is_container[k]) containers_.push_back(static_cast<int>(k));
    else if (wc.related(device, static_cast<int>(k))) stands_on_.push_back(static_cast<int>(k));
  }
  const Device& d = *geometry.objects[device].device;
  tool_parts_ = d.tool_parts();
  moved_ = d.moved_parts();
  plane_ = floor_z(wc, geometry);
  blocks_ = floor_blocks(wc, geometry);
}

std::optional<Collision> DeviceClearance::at(CollisionWorld& world, const Eigen::VectorXd& q, int target, bool first,
                                             const std::vector<int>& ignore, const HeldLoad& load) const {
  const ObjectGeometry& g = geometry_.objects[device_];
  std::vector<Eigen::Isometry3d> X = g.device->part_poses(q);
  for (auto& x : X) x = g.X_world_object * x;
  std::vector<int> skip = containers_;
  skip.insert(skip.end(), ignore.begin(), ignore.end());
  for (const auto& [o, X_tool_o] : load.objects) skip.push_back(o);  // the tool holds them
  auto c = world.device_collision(device_, X, skip, target, tool_parts_, stands_on_, first);
  if (!c) c = world.into_floors(device_, X, moved_, plane_, blocks_);
  if (load.empty() || (c && first)) return c;
  const Eigen::Isometry3d X_world_tool = X[g.device->tool_part] * g.device->X_part_tool;
  std::vector<std::pair<int, Eigen::Isometry3d>> held;
  for (const auto& [o, X_tool_o] : load.objects) held.emplace_back(o, X_world_tool * X_tool_o);
  keep_deepest(c, world.held_collision(device_, X, held, skip, target, tool_parts_, first, plane_, blocks_));
  return c;
}

std::optional<Collision> DeviceClearance::of_parts(CollisionWorld& world, const Eigen::VectorXd& q, int target,
                                                   const std::vector<char>& parts, const HeldLoad& load) const {
  const ObjectGeometry& g = geometry_.objects[device_];
  std::vector<Eigen::Isometry3d> X = g.device->part_poses(q);
  for (auto& x : X) x = g.X_world_object * x;
  std::vector<int> skip = containers_;
  for (const auto& [o, X_tool_o] : load.objects) skip.push_back(o);
  return world.device_collision(device_, X, skip, target, tool_parts_, stands_on_, false, parts);
}

Eigen::Isometry3d CollisionWorld::placed_pose(int object) {
  const ObjectGeometry& g = impl_->geometry.objects[object];
  const auto& shapes = impl_->of(object);
  if (shapes.empty()) return g.X_world_object;
  return Eigen::Isometry3d(shapes.front()->getTransform().matrix()) * g.shapes.front().X_object_shape.inverse();
}

void CollisionWorld::move(int object, const Eigen::Isometry3d& X_world_object) {
  const ObjectGeometry& g = impl_->geometry.objects[object];
  std::vector<Eigen::Isometry3d>& X = impl_->scratch;
  X.resize(g.shapes.size());
  for (size_t k = 0; k < g.shapes.size(); ++k) X[k] = X_world_object * g.shapes[k].X_object_shape;
  impl_->place(object, X);
}

void CollisionWorld::move_parts(int object, const std::vector<Eigen::Isometry3d>& X_world_part) {
  const ObjectGeometry& g = impl_->geometry.objects[object];
  const std::vector<Eigen::Isometry3d>& X_part_shape = impl_->in_parts(object);
  std::vector<Eigen::Isometry3d>& X = impl_->scratch;
  X.resize(g.shapes.size());
  std::vector<Eigen::Isometry3d>& then = impl_->parts_at[object];
  const bool known = then.size() == X_world_part.size();
  impl_->place(object, [&](size_t k) -> const Eigen::Isometry3d* {
    const int p = g.shapes[k].part;
    if (known && then[p].matrix() == X_world_part[p].matrix()) return nullptr;
    X[k] = compose(X_world_part[p], X_part_shape[k]);
    return &X[k];
  });
  then = X_world_part;
}

std::vector<Proximity> CollisionWorld::proximity(int object, const std::vector<int>& skip, double reach,
                                                 const std::function<double(int other)>& below,
                                                 const std::vector<char>& parts) {
  std::vector<Proximity> out;
  const auto& mine = impl_->of(object);
  if (mine.empty()) return out;
  // The bounds of the shapes measured: of the parts asked for only (a crane's moving hook, not
  // its runway along the whole hall).
  fcl::AABBd box = impl_->bounds(object);
  if (!parts.empty()) {
    bool any = false;
    for (size_t i = 0; i < mine.size(); ++i) {
      const int part = impl_->geometry.objects[object].shapes[i].part;
      if (part < 0 || !parts[part]) continue;
      if (!any) box = mine[i]->getAABB();
      else box += mine[i]->getAABB();
      any = true;
    }
    if (!any) return out;
  }
  const auto& objects = impl_->geometry.objects;
  impl_->bounds(object);  // (every object's bounds filled)
  const std::vector<fcl::AABBd>& boxes = impl_->boxes;
  for (size_t o = 0; o < objects.size(); ++o) {
    int other = static_cast<int>(o);
    // Boxes apart bound the distance from below; overlapping boxes bound no depth (a pair seen
    // overlapping, limit < 0, was never measured again: its deepest went unseen). The reach
    // first, one axis at a time (each object of a store's 200 is looked at several times a
    // sample): asking `below` of each at each sample was a tenth of a campaign's time.
    const fcl::AABBd& theirs = boxes[o];
    bool beyond = false;
    for (int k = 0; k < 3 && !beyond; ++k) {
      const double apart = std::max(box.min_[k] - theirs.max_[k], theirs.min_[k] - box.max_[k]);
      beyond = apart > reach && apart > 0;  // the boxes' gap is at least that
    }
    if (beyond || other == object || objects[o].shapes.empty()) continue;
    if (std::find(skip.begin(), skip.end(), other) != skip.end()) continue;
    const double gap = box_gap(box, theirs);
    if (gap > reach && gap > 0) continue;
    const double limit = below ? std::min(reach, below(other)) : reach;
    if (gap > limit && gap > 0) continue;
    const std::optional<Proximity> best = impl_->nearest(object, other, limit, parts);
    if (best && best->distance < limit) out.push_back(*best);
  }
  return out;
}

std::optional<Proximity> CollisionWorld::pair_distance(int object, int other, const std::vector<char>& parts, double below) {
  if (impl_->of(object).empty() || impl_->of(other).empty()) return std::nullopt;
  return impl_->nearest(object, other, below, parts);
}

namespace {
/// The most n·x over a placed shape's points (n a unit vector): exact for the primitives, the
/// world box's for a mesh (a box around it reaches at least as far).
double support(const fcl::CollisionObjectd& o, const Eigen::Vector3d& n) {
  const Shape& s = shape_of(&o);
  const fcl::Transform3d& X = o.getTransform();
  const Eigen::Vector3d u = X.linear().transpose() * n;  // n in the shape's frame
  const double at = n.dot(X.translation());
  switch (s.kind) {
    case Shape::Kind::Box: return at + 0.5 * (std::abs(u.x()) * s.box_size.x() + std::abs(u.y()) * s.box_size.y() + std::abs(u.z()) * s.box_size.z());
    case Shape::Kind::Cylinder: return at + s.radius * std::hypot(u.x(), u.y()) + 0.5 * s.length * std::abs(u.z());
    case Shape::Kind::Sphere: return at + s.radius;
    case Shape::Kind::Mesh: break;
  }
  const fcl::AABBd& box = o.getAABB();
  double most = 0;
  for (int k = 0; k < 3; ++k) most += std::max(n[k] * box.min_[k], n[k] * box.max_[k]);
  return most;
}
}  // namespace

std::optional<double> CollisionWorld::slab_bound(int object, int other, const std::vector<char>& parts,
                                                 const std::vector<std::vector<Eigen::Vector3d>>& shifts) {
  const std::optional<Proximity> near = pair_distance(object, other, parts);
  if (!near || near->distance <= 0 || near->shape < 0 || near->other_shape < 0) return std::nullopt;
  const auto& mine = impl_->of(object);
  const auto& theirs = impl_->of(other);
  // Their nearest points, from the nearest shapes.
  fcl::DistanceRequestd req(true, false, 1e-9, 1e-9, 1e-9, fcl::GST_INDEP);
  fcl::DistanceResultd res;
  fcl::distance(mine[near->shape].get(), theirs[near->other_shape].get(), req, res);
  const Eigen::Vector3d gap = res.nearest_points[1] - res.nearest_points[0];
  if (!(gap.norm() > 1e-9)) return std::nullopt;
  const Eigen::Vector3d n = gap.normalized();
  double least = INFINITY;
  for (const auto& o : theirs) least = std::min(least, -support(*o, -n));
  const ObjectGeometry& g = impl_->geometry.objects[object];
  double most = -INFINITY;
  for (size_t i = 0; i < mine.size(); ++i) {
    const int part = g.shapes[i].part;
    if (!parts.empty() && (part < 0 || !parts[part])) continue;
    const std::vector<Eigen::Vector3d>& mine_shifts = shifts.at(g.device && part >= 0 ? static_cast<size_t>(part) : 0);
    double ahead = 0;  // (no shift at all is where it is now)
    for (const Eigen::Vector3d& d : mine_shifts) ahead = std::max(ahead, n.dot(d));
    most = std::max(most, support(*mine[i], n) + ahead);
  }
  return least - most;
}

double CollisionWorld::travel_bound(int object, int part, const Eigen::Isometry3d& from, const Eigen::Isometry3d& to) {
  return moved(from, to, impl_->reach(object, part));
}

double CollisionWorld::descent_bound(int object, int part, const Eigen::Isometry3d& from, const Eigen::Isometry3d& to) {
  const double reach = impl_->reach(object, part);
  const Eigen::AngleAxisd turn(to.linear() * from.linear().transpose());
  // A point's displacement by the turn is perpendicular to its axis u: its z share is at most
  // sqrt(1 - u_z^2) of it.
  const double across = turn.angle() > 0 ? std::sqrt(std::max(0.0, 1 - turn.axis().z() * turn.axis().z())) : 0.0;
  return std::max(0.0, from.translation().z() - to.translation().z()) + turn.angle() * reach * across +
         reach * (1 - std::cos(turn.angle() / 2));
}

double CollisionWorld::lowest(int object, const std::vector<char>& parts) {
  const auto& mine = impl_->of(object);
  double low = INFINITY;
  for (size_t i = 0; i < mine.size(); ++i) {
    const int part = impl_->geometry.objects[object].shapes[i].part;
    if (!parts.empty() && (part < 0 || !parts[part])) continue;
    // The lowest corner of the shape's own box where it is turned (FCL's world box of a turned
    // shape is the box of its bounding sphere: a pallet turned about z reached 0.5 m below the
    // floor it was carried above).
    const fcl::CollisionGeometryd& g = *mine[i]->collisionGeometry();
    const Eigen::Matrix3d R = mine[i]->getRotation();
    const Eigen::Vector3d half = (g.aabb_local.max_ - g.aabb_local.min_) / 2, centre = (g.aabb_local.max_ + g.aabb_local.min_) / 2;
    const double z = (R * centre + mine[i]->getTranslation()).z() - R.row(2).cwiseAbs().dot(half);
    low = std::min(low, std::max(z, mine[i]->getAABB().min_.z()));
  }
  return low;
}

bool CollisionWorld::self_clear(int object, double gap) {
  const ObjectGeometry& g = impl_->geometry.objects[object];
  if (!g.device) return true;
  const auto& mine = impl_->of(object);
  for (size_t i = 0; i < mine.size(); ++i)
    for (size_t k = i + 1; k < mine.size(); ++k) {
      const int a = g.shapes[i].part, b = g.shapes[k].part;
      if (a == b || g.device->may_touch(a, b) || box_gap(mine[i]->getAABB(), mine[k]->getAABB()) > gap) continue;
      if (signed_distance(mine[i].get(), mine[k].get()) <= gap) return false;
    }
  return true;
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

namespace {

/// Closest point to p on triangle abc (Ericson, Real-Time Collision Detection, 5.1.5).
Eigen::Vector3d closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c) {
  Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  Eigen::Vector3d bp = p - b;
  double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  Eigen::Vector3d cp = p - c;
  double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  double denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

/// Whether p is inside a closed triangle mesh: its winding number, the sum of the solid angles
/// its triangles subtend (Van Oosterom and Strackee), is 1 inside and 0 outside. Unlike a ray's
/// crossings it has no unlucky directions, and pieces that touch or overlap (a pallet's boards
/// and blocks) count as their union.
bool inside_mesh(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& v, const std::vector<Eigen::Vector3i>& tris) {
  double solid_angle = 0;
  for (const Eigen::Vector3i& t : tris) {
    const Eigen::Vector3d a = v[t.x()] - p, b = v[t.y()] - p, c = v[t.z()] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    solid_angle += 2 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
  }
  return std::abs(solid_angle) > 2 * std::numbers::pi;  // a winding number above one half (either orientation)
}

/// Points of a shape that decide containment: box corners and mesh vertices (exact for convex
/// containers), tessellation vertices for cylinders and spheres (within 0.5% of the radius).
std::vector<Eigen::Vector3d> hull_points(const Shape& s, const Eigen::Isometry3d& X) {
  std::vector<Eigen::Vector3d> out;
  Shape local = s;
  local.X_object_shape.setIdentity();
  TriangleMesh m = tessellate(local);
  for (const Eigen::Vector3d& p : m.vertices) out.push_back(X * p);
  return out;
}

}  // namespace

std::optional<double> inside_margin(const GeometryModel& geometry, int object, int container, std::string* why,
                                    uint8_t faces, double min, std::string* through, int part, double* uncounted) {
  const ObjectGeometry& c = geometry.objects[container];
  if (c.shapes.size() != 1 || c.shapes[0].kind == Shape::Kind::Sphere) {
    *why = "the container must have exactly one box, cylinder or mesh shape (its inside)";
    return std::nullopt;
  }
  const ObjectGeometry& g = geometry.objects[object];
  if (g.shapes.empty()) {
    *why = "the object has no geometry";
    return std::nullopt;
  }
  const Shape& cs = c.shapes[0];
  const Eigen::Isometry3d X_c_world = (c.X_world_object * cs.X_object_shape).inverse();
  const Eigen::Isometry3d X_c_object = X_c_world * g.X_world_object;  // once, not per shape
  // Per face: the smallest distance of the object inside it (negative: protrusion). Counted faces
  // give the margin less `min`; any protrusion fails, counted or not.
  double counted = INFINITY, protrusion = 0;
  if (uncounted) *uncounted = INFINITY;
  auto face = [&](uint8_t bit, double distance, const char* name = "") {
    if (faces & bit) counted = std::min(counted, distance - min);
    else if (uncounted) *uncounted = std::min(*uncounted, distance);
    if (distance < protrusion && through) *through = name;
    protrusion = std::min(protrusion, distance);
  };
  auto judged = [part](const Shape& s) { return part < 0 || s.part == part; };
  auto result = [&]() { return protrusion < 0 ? std::min(protrusion, counted) : counted; };
  switch (cs.kind) {
    case Shape::Kind::Box: {
      // Bounds in the box's own frame are exact for boxes, cylinders and spheres at any rotation.
      Eigen::Vector3d half = cs.box_size / 2;
      Eigen::AlignedBox3d b;
      for (const Shape& s : g.shapes)
        if (judged(s)) b.extend(shape_bounds(s, compose(X_c_object, s.X_object_shape)));
      if (b.isEmpty()) return INFINITY;  // the part has no shape
      static constexpr const char* kNames[3][2] = {{"its x- face", "its x+ face"}, {"its y- face", "its y+ face"}, {"its floor", "its top"}};
      for (int k = 0; k < 3; ++k) {
        face(static_cast<uint8_t>(1 << (2 * k)), b.min()[k] + half[k], kNames[k][0]);
        face(static_cast<uint8_t>(2 << (2 * k)), half[k] - b.max()[k], kNames[k][1]);
      }
      return result();
    }
    case Shape::Kind::Cylinder: {
      if ((faces & SpatialCheck::Walls) != 0 && (faces & SpatialCheck::Walls) != SpatialCheck::Walls) {
        *why = "a cylinder's faces are walls (its round side), z- and z+";
        return std::nullopt;
      }
      // Along the axis: exact bounds; radially: the farthest point from the axis.
      double half = cs.length / 2;
      for (const Shape& s : g.shapes) {
        if (!judged(s)) continue;
        Eigen::Isometry3d X = compose(X_c_object, s.X_object_shape);
        Eigen::AlignedBox3d b = shape_bounds(s, X);
        face(SpatialCheck::ZMin, b.min().z() + half, "its bottom");
        face(SpatialCheck::ZMax, half - b.max().z(), "its top");
        double radial = 0;
        if (s.kind == Shape::Kind::Sphere) {
          radial = X.translation().head<2>().norm() + s.radius;
        } else {
          for (const Eigen::Vector3d& p : hull_points(s, X)) radial = std::max(radial, p.head<2>().norm());
        }
        face(SpatialCheck::Walls, cs.radius - radial, "its round side");
      }
      return result();
    }
    case Shape::Kind::Mesh: {
      if (!cs.mesh->closed) {
        *why = fmt::format("the container's mesh '{}' is open (a surface, no inside): inside needs a closed mesh",
                           std::filesystem::path(cs.mesh->path).filename().string());
        return std::nullopt;
      }
      if (faces != SpatialCheck::All) {
        *why = "a mesh container has no named faces: use faces: all";
        return std::nullopt;
      }
      // Every point of the object's hull inside the closed mesh; margin: the distance from the
      // nearest point to the surface, or minus the farthest outside point's distance.
      std::vector<Eigen::Vector3d> v;
      for (const Eigen::Vector3d& p : cs.mesh->vertices) v.push_back(p.cwiseProduct(cs.scale));
      const auto& tris = cs.mesh->triangles;
      double margin = INFINITY, worst_outside = 0;
      bool any_outside = false;
      for (const Shape& s : g.shapes)
        for (const Eigen::Vector3d& p : judged(s) ? hull_points(s, X_c_object * s.X_object_shape) : std::vector<Eigen::Vector3d>()) {
          double d = surface_distance(p, v, tris);
          if (inside_mesh(p, v, tris)) {
            margin = std::min(margin, d);
          } else {
            any_outside = true;
            worst_outside = std::max(worst_outside, d);
          }
        }
      face(SpatialCheck::All, any_outside ? -worst_outside : margin);
      return result();
    }
    default: return std::nullopt;
  }
}

}  // namespace sscs
