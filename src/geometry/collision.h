#pragma once
/// Distances, overlaps and containment between objects' geometry, through FCL.
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "geometry/geometry.h"

namespace sscs {

/// FCL collision objects for the shapes of a GeometryModel, built on first use per object.
/// Not copyable; one per check run.
class CollisionWorld {
 public:
  explicit CollisionWorld(const GeometryModel& geometry);
  ~CollisionWorld();
  CollisionWorld(const CollisionWorld&) = delete;
  CollisionWorld& operator=(const CollisionWorld&) = delete;

  /// Signed distance between two objects' geometry: the smallest distance between any of their
  /// shapes, or minus the largest penetration depth when they interpenetrate. nullopt when one
  /// of them has no geometry.
  std::optional<double> distance(int a, int b);

  /// Pairs (a < b) of `objects` whose world bounding boxes, grown by `margin`, touch: found by a
  /// dynamic AABB tree broadphase, not by testing all pairs. Sorted.
  std::vector<std::pair<int, int>> candidate_pairs(const std::vector<int>& objects, double margin);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// How far `object` lies within `container` (a single box: a room's box is its inside): the
/// smallest distance from the object's geometry to the box's faces when inside, minus the
/// largest protrusion when not. nullopt (with `why`) when the container is not one box or an
/// object has no geometry.
std::optional<double> inside_margin(const GeometryModel& geometry, int object, int container, std::string* why);

}  // namespace sscs
